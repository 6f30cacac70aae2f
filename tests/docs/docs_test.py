#!/usr/bin/env python3
"""Fails when the user documentation is stale (CTest label `docs`; no build needed).

Checks, from the sources (regular expressions, no compilation):
  (a) every subcommand and long flag of the CLI (CLI11 add_subcommand / add_option / add_flag in
      bench/app/*.cc) appears in docs/cli.md;
  (b) every YAML key the scenario and target parsers accept (the field declarations, CheckKeys
      lists and key vectors of bench/config/*.cc and io/*.cc, and the method options of
      VisitOptions in methods/*.cc) appears in docs/configuration.md (its reference part is generated:
      tests/docs/config_reference_test.sh checks that it is current);
  (c) every CSV column (the metric table's quantities and their err_/std_/crlb_/est_/true_
      columns, metrics/metric_table.cc; the outputs the method types declare, the OutputSpec
      declarations of methods/*.cc; the column declarations of bench/run/*.cc; the CSV headers
      written by bench/app/*.cc) appears in docs/outputs.md;
  (d) no issue references ("issue #N", "(#N)") and no development history in README.md, docs/
      and the READMEs a user reads beside the files they describe (data/, configs/,
      tests/fixtures/);
  (e) README.md has at most 220 lines;
  (f) every relative link of README.md and docs/**/*.md points to an existing file inside the
      repository;
  (g) the two source documents are cited by name (the Clemson adaptive-calibration thesis, Algers
      2018), never by their number in the project's notes, and no issue number appears anywhere
      in the sources (docs, code comments, the report's text, tools, fuzz dictionaries, configs).

Run: /usr/bin/python3 tests/docs/docs_test.py [REPO_ROOT]
"""
import glob
import os
import re
import sys
import unittest

ROOT = os.path.abspath(
    sys.argv[1] if len(sys.argv) > 1 and not sys.argv[1].startswith("-")
    else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


def read(path):
    """A file of the repository (a path relative to ROOT, or absolute)."""
    with open(os.path.join(ROOT, path), encoding="utf-8") as f:
        return f.read()


def sources(pattern):
    return sorted(glob.glob(os.path.join(ROOT, pattern)))


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def literals(text):
    return re.findall(r'"((?:[^"\\]|\\.)*)"', text)


def call_arguments(text, start):
    """The text from `start` (just after an opening parenthesis) to its matching ')'."""
    depth, i = 1, start
    while i < len(text) and depth:
        c = text[i]
        if c == '"':
            i += 1
            while i < len(text) and text[i] != '"':
                i += 2 if text[i] == "\\" else 1
        elif c == "(":
            depth += 1
        elif c == ")":
            depth -= 1
        i += 1
    return text[start:i - 1]


def braced_lists(text):
    """Every {...} initializer list of string literals in `text` (innermost braces)."""
    return [literals(m.group(1)) for m in re.finditer(r"\{([^{}]*)\}", text)
            if literals(m.group(1)) and re.fullmatch(r'[\s,]*("(?:[^"\\]|\\.)*"[\s,]*)+',
                                                      m.group(1))]


def code_tokens(markdown):
    """The words inside `code spans` and ``` blocks of a markdown text."""
    spans = re.findall(r"```.*?```", markdown, flags=re.S)
    rest = re.sub(r"```.*?```", "", markdown, flags=re.S)
    spans += re.findall(r"`([^`\n]+)`", rest)
    tokens = set()
    for span in spans:
        tokens.update(re.findall(r"[A-Za-z0-9_+.\-]+", span))
        tokens.update(re.findall(r"[A-Za-z0-9_]+", span))
    return tokens


# ---------------------------------------------------------------------------------------------
# What the sources declare.

def cli_names():
    subcommands, flags = set(), set()
    for path in sources("bench/app/*.cc"):
        text = strip_comments(read(path))
        for m in re.finditer(r"add_(subcommand|option|flag)\s*\(", text):
            args = call_arguments(text, m.end())
            first = literals(args[:args.find(",")] if "," in args else args)
            if not first:
                continue
            if m.group(1) == "subcommand":
                subcommands.add(first[0])
            else:
                flags.update(n for n in first[0].split(",") if n.startswith("--"))
    return subcommands, flags


def config_keys():
    keys = set()
    for path in sources("bench/config/*.cc") + sources("io/*.cc"):
        text = strip_comments(read(path))
        # CheckKeys(node, field, {"a", "b"}), ParseCamera's extra keys, and the vectors / sets
        # handed to them.
        for m in re.finditer(r"\b(?:CheckKeys|ParseCamera)\s*\(", text):
            for lst in braced_lists(call_arguments(text, m.end())):
                keys.update(lst)
        for m in re.finditer(
                r"(?:std::vector<std::string>|std::set<std::string>)\s+(?:const\s+)?"
                r"(?:keys|times|allowed)\s*=\s*", text):
            start = text.find("{", m.end())
            depth, i = 0, start
            while i < len(text):
                depth += {"{": 1, "}": -1}.get(text[i], 0)
                i += 1
                if depth == 0:
                    break
            for lst in braced_lists(text[start:i]):
                keys.update(lst)
        for m in re.finditer(r"(?:keys|times|allowed)\.insert\s*\(", text):
            for lst in braced_lists(call_arguments(text, m.end())):
                keys.update(lst)
        # The sweepable top-level fields.
        m = re.search(r"SweepableKeys\(\)\s*\{(.*?)return", text, flags=re.S)
        if m:
            for lst in braced_lists(m.group(1)):
                keys.update(lst)
    # The declarations of the scenario format (Visit per struct, scenario_fields.cc and
    # source_fields.cc): the key of
    # every FieldSpec handed to a visitor.
    for path in sources("bench/config/*.cc") + sources("io/*.cc"):
        text = strip_comments(read(path))
        keys.update(re.findall(
            r"\b(?:Field|Section|List|VisitEnum|VisitSection|VisitList|Refused)\s*\(\s*"
            r"(?:[A-Za-z_]\w*\s*,\s*)?\{?\s*\"([A-Za-z0-9_]+)\"", text))
    # Method options: VisitOptions of every method type (and the shared online options): the key
    # of every OptionSpec, `Field({"key", "unit", "doc"}, &member)` or `EnumOption(v, {...}, ...)`.
    for path in sources("methods/*.cc") + sources("methods/*.h"):
        text = strip_comments(read(path))
        keys.update(re.findall(
            r"\b(?:Field(?:OrAll)?|EnumOption)\s*\(\s*(?:[A-Za-z_]\w*\s*,\s*)?\{?\s*\"([A-Za-z0-9_]+)\"",
            text))
    # Tracked quantities (tracking.tolerance keys) are the metric table's tracked names.
    keys.update(name for name, _, tracked in metric_entries() if tracked)
    return keys


def metric_entries():
    """(name, columns, tracked) of every Entry of metrics/metric_table.cc."""
    text = strip_comments(read("metrics/metric_table.cc"))
    body = text[text.find("MakeTable()"):]
    entries = []
    parts = re.split(r"\bEntry\s*\(", body)[1:]
    for part in parts:
        names = literals(part)
        if not names:
            continue
        cols = re.search(r"\.Columns\s*\(\s*(\w+)\s*\)", part)
        entries.append((names[0], cols.group(1) if cols else "kValueColumn",
                        ".Track(" in part))
    return entries


def method_outputs():
    """(names, problems): the name of every OutputSpec a method type declares (methods/*.cc and
    *.h): `OutputSpec kName = {"name", ...}`, `OutputSpec kName{"name", ...}`, a temporary
    `OutputSpec{"name", ...}`, or an initializer `{"name", ...}` in an Outputs() override's
    body. problems names the files with a non-empty Outputs() override that neither holds such an
    initializer nor returns a constant declared so, so that a new way of writing one fails
    instead of going unchecked."""
    names, constants, overrides = set(), set(), []
    for path in sources("methods/*.cc") + sources("methods/*.h"):
        text = strip_comments(read(path))
        for constant, name in re.findall(
                r'\bOutputSpec\s*([A-Za-z_]\w*)?\s*(?:=\s*)?\{\s*"([a-z][a-z0-9_]*)"', text):
            names.add(name)
            constants.add(constant)
        for m in re.finditer(r"\bOutputs\s*\(\s*\)\s*const\b[^{;]*\{", text):
            depth, i = 1, m.end()
            while i < len(text) and depth:
                depth += {"{": 1, "}": -1}.get(text[i], 0)
                i += 1
            body = text[m.end():i - 1]
            if not re.fullmatch(r"\s*return\s*\{\s*\}\s*;\s*", body):
                inline = re.findall(r'\{\s*"([a-z][a-z0-9_]*)"', body)
                names.update(inline)
                overrides.append((os.path.relpath(path, ROOT), bool(inline),
                                  set(re.findall(r"\b[A-Za-z_]\w*\b", body))))
    problems = sorted({path for path, inline, words in overrides
                       if not inline and not words & constants})
    return names, problems


def column_names():
    columns = set()
    prefixes = {"kIntrinsic": ["", "err_", "std_", "crlb_"], "kParameter": ["", "err_"],
                "kValueColumn": [""]}
    for name, cols, tracked in metric_entries():
        for prefix in prefixes.get(cols, [""]):
            columns.add(prefix + name)
        if tracked:
            columns.update({"est_" + name, "true_" + name, "err_" + name})
    # The method types' declared outputs: runs.csv columns of their own.
    columns.update(method_outputs()[0])
    # Column declarations {"name", "unit", "doc"} of the run directory writers.
    for path in sources("bench/run/*.cc"):
        text = strip_comments(read(path))
        columns.update(re.findall(
            r'\{\s*"([a-z][a-z0-9_]*)"\s*,\s*"(?:px|deg|m|s|ms|us|px2|)"\s*,', text))
    # CSV headers written by the commands: CsvLine({"a", "b", ...}) of literals only.
    for path in sources("bench/app/*.cc") + sources("bench/run/*.cc"):
        text = strip_comments(read(path))
        for m in re.finditer(r"CsvLine\s*\(", text):
            for lst in braced_lists(call_arguments(text, m.end())):
                columns.update(lst)
    return columns


def markdown_files():
    files = ["README.md"] + [os.path.relpath(p, ROOT)
                             for p in sources("docs/**/*.md") + sources("docs/*.md")]
    return sorted(set(files))


# The READMEs beside the files they describe, read by users as the documentation is.
USER_READMES = ["data/README.md", "configs/README.md", "tests/fixtures/README.md"]


# The source files (g) scans: text a user or a developer reads. CHANGELOG.md is history.
SOURCE_EXTENSIONS = (".md", ".h", ".cc", ".py", ".sh", ".cmake", ".txt", ".yaml", ".dict", ".toml")
SKIPPED_DIRS = {".git", "out", "report"}


def source_files():
    for base, dirs, files in os.walk(ROOT):
        dirs[:] = sorted(d for d in dirs if d not in SKIPPED_DIRS and not d.startswith("build"))
        for f in sorted(files):
            path = os.path.relpath(os.path.join(base, f), ROOT)
            if (f.endswith(SOURCE_EXTENSIONS) or os.path.dirname(path) == "scripts") and \
                    path != "CHANGELOG.md" and os.path.getsize(os.path.join(ROOT, path)) < 2**20:
                yield path


# ---------------------------------------------------------------------------------------------

class DocsTest(unittest.TestCase):

    def test_a_cli_reference_lists_every_subcommand_and_flag(self):
        subcommands, flags = cli_names()
        self.assertGreaterEqual(len(subcommands), 8, "the CLI parse found too few subcommands")
        self.assertGreaterEqual(len(flags), 20, "the CLI parse found too few flags")
        cli = read("docs/cli.md")
        headings = set(re.findall(r"^#+\s+(\S+)\s*$", cli, flags=re.M))
        missing = sorted(s for s in subcommands if s not in headings)
        self.assertEqual(missing, [], "subcommands without a section in docs/cli.md")
        missing = sorted(f for f in flags if not re.search(re.escape(f) + r"(?![\w-])", cli))
        self.assertEqual(missing, [], "flags missing from docs/cli.md")

    def test_b_configuration_reference_lists_every_key(self):
        keys = config_keys()
        self.assertGreaterEqual(len(keys), 100, "the parser scan found too few keys")
        for expected in ("changes", "tracking", "window_s", "every_s", "forgetting_beta",
                         "reset_threshold", "role", "q_focal_px2_s", "blur_grid"):
            self.assertIn(expected, keys, "the parser scan missed a known key")
        documented = code_tokens(read("docs/configuration.md"))
        missing = sorted(k for k in keys if k not in documented)
        self.assertEqual(missing, [], "keys missing from docs/configuration.md")

    def test_c_outputs_reference_lists_every_column(self):
        _, unrecognised = method_outputs()
        self.assertEqual(unrecognised, [], "Outputs() overrides whose OutputSpec declarations "
                         "the scan does not recognise")
        columns = column_names()
        self.assertGreaterEqual(len(columns), 100, "the column scan found too few columns")
        for expected in ("fku_px", "err_fku_px", "std_u0_px", "crlb_phi_deg", "est_pitch_deg",
                         "wall_per_frame_us", "reconverge_s", "wall_per_tag_us", "in_view",
                         "pe_min_eig"):
            self.assertIn(expected, columns, "the column scan missed a known column")
        documented = code_tokens(read("docs/outputs.md"))
        missing = sorted(c for c in columns if c not in documented)
        self.assertEqual(missing, [], "columns missing from docs/outputs.md")

    def test_d_no_issue_references_or_history(self):
        history = ["code not kept", "tried, measured", "not landed", "(was "]
        problems = []
        for path in markdown_files() + USER_READMES:
            for n, line in enumerate(read(path).splitlines(), 1):
                if re.search(r"issue\s*#\s*\d+", line, flags=re.I) or \
                        re.search(r"(?<![\w/&#])#\d+\b", line):
                    problems.append(f"{path}:{n}: issue reference: {line.strip()}")
                for phrase in history:
                    if phrase in line.lower():
                        problems.append(f"{path}:{n}: history ({phrase!r}): {line.strip()}")
        self.assertEqual(problems, [], "README.md, docs/ and " + ", ".join(USER_READMES) +
                         " must not cite issues or history")

    def test_g_sources_cited_by_name_and_no_issue_numbers(self):
        problems = []
        for path in source_files():
            with open(os.path.join(ROOT, path), encoding="utf-8", errors="replace") as f:
                for n, line in enumerate(f, 1):
                    if re.search(r"\bseed\s*0\d\d\b", line, flags=re.I):
                        problems.append(f"{path}:{n}: a source cited by number: {line.strip()}")
                    if re.search(r"\bissue\s*#\s*\d+", line, flags=re.I):
                        problems.append(f"{path}:{n}: issue reference: {line.strip()}")
        self.assertEqual(problems, [], "cite the Clemson adaptive-calibration thesis and Algers "
                         "2018 by name, and state a target's reason instead of its issue")

    def test_e_readme_is_short(self):
        lines = read("README.md").count("\n")
        self.assertLessEqual(lines, 220, "README.md is a front page: at most 220 lines")

    def test_f_relative_links_resolve_inside_the_repository(self):
        problems = []
        for path in markdown_files():
            text = re.sub(r"```.*?```", "", read(path), flags=re.S)
            for target in re.findall(r"\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)", text):
                if re.match(r"^[a-z][a-z0-9+.-]*:", target, flags=re.I) or target.startswith("#"):
                    continue
                file_part = target.split("#", 1)[0]
                resolved = os.path.normpath(os.path.join(ROOT, os.path.dirname(path), file_part))
                if not (resolved == ROOT or resolved.startswith(ROOT + os.sep)):
                    problems.append(f"{path}: {target}: outside the repository")
                elif not os.path.exists(resolved):
                    problems.append(f"{path}: {target}: no such file")
        self.assertEqual(problems, [], "broken relative links")


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0]], verbosity=2)
