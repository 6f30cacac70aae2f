#!/usr/bin/env python3
"""docs/tutorial.md, run as a newcomer would: every command of its sections 2 (write your own
scenario), 3 (calibrate your camera from images) and 4 (calibrate a stereo camera), in a fresh directory that sees the
repository's configs/ and data/, with calibench on the PATH.

The user's own images (my_images/, new_images/) and target (board.yaml) are the bundled
opencv-left chessboard set and its target file (and for the stereo camera the opencv-left and
opencv-right pair). Section 1 (./scripts/bench, about six minutes on
2 cores) and section 5 (Slurm: scripts/slurm_ci.sh) are steps of CI's .ci/run.

Usage: tutorial_test.py SOURCE_DIR CALIBENCH
"""
import os
import re
import shlex
import subprocess
import sys
import tempfile

# What a newcomer has that this test has to stand in for.
SUBSTITUTIONS = [  # (a whole word of a command line, what replaces it)
    ("my_images/", "data/opencv-left/"),
    ("new_images/", "data/opencv-left/"),
    ("board.yaml", "data/opencv-left/checkerboard.yaml"),
    ("my_images/left*.jpg", "data/opencv-left/left*.jpg"),
    ("my_images/right*.jpg", "data/opencv-right/right*.jpg"),
    ("new_images/left*.jpg", "data/opencv-left/left*.jpg"),
    ("new_images/right*.jpg", "data/opencv-right/right*.jpg"),
]
SECTIONS = ("## 2.", "## 3.", "## 4.")


def blocks(markdown, language):
    """(section heading, block text) of every fenced block in `language`."""
    section = ""
    out = []
    lines = markdown.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("## "):
            section = line
        if line.strip() == "```" + language:
            indent = line[: len(line) - len(line.lstrip())]
            body = []
            i += 1
            while lines[i].strip() != "```":
                body.append(lines[i][len(indent):] if lines[i].startswith(indent) else lines[i])
                i += 1
            out.append((section, "\n".join(body)))
        i += 1
    return out


def commands(block):
    """The block's command lines, comments dropped."""
    for line in block.splitlines():
        line = re.sub(r"\s+#.*$", "", line).strip()
        if line and not line.startswith("#"):
            yield line


def main():
    source_dir, calibench = sys.argv[1], os.path.abspath(sys.argv[2])
    with open(os.path.join(source_dir, "docs", "tutorial.md"), encoding="utf-8") as f:
        tutorial = f.read()
    ran = 0
    with tempfile.TemporaryDirectory() as work:
        for name in ("configs", "data"):
            os.symlink(os.path.join(source_dir, name), os.path.join(work, name))
        env = dict(os.environ, PATH=os.path.dirname(calibench) + os.pathsep + os.environ["PATH"])
        for section, body in blocks(tutorial, "yaml"):
            if section.startswith("## 2."):  # The scenario the section writes.
                with open(os.path.join(work, "my_scene.yaml"), "w", encoding="utf-8") as f:
                    f.write(body + "\n")
        for section, body in blocks(tutorial, "sh"):
            if not section.startswith(SECTIONS):
                continue
            for line in commands(body):
                argv = [dict(SUBSTITUTIONS).get(word, word) for word in shlex.split(line)]
                result = subprocess.run(argv, cwd=work, env=env, capture_output=True, text=True,
                                        check=False)
                if result.returncode != 0:
                    print(f"FAILED ({section}): {line}\nexit {result.returncode}\n"
                          f"{result.stdout[-2000:]}\n{result.stderr[-2000:]}")
                    return 1
                print("ok: " + shlex.join(argv))
                ran += 1
        # What the commands promise to leave behind.
        for path in ("out/my_scene/runs.csv", "out/my_scene/config.resolved.yaml",
                     "board.pdf", "camera.yaml"):
            if not os.path.exists(os.path.join(work, path)):
                print(f"FAILED: {path} was not written")
                return 1
    if ran < 8:
        print(f"FAILED: only {ran} commands found in the tutorial's sections 2 and 3")
        return 1
    print(f"{ran} tutorial commands ran")
    return 0


if __name__ == "__main__":
    sys.exit(main())
