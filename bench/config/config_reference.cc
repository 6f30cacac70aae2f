// The reference of the scenario format (`calibench config-reference`, the generated part of
// docs/configuration.md): tables written from the declarations (scenario_fields.cc) and from the
// VisitOptions of every registered method type; the latter alone is `calibench methods`.
#include "bench/config/config_reference.h"

#include <cmath>
#include <sstream>

#include "bench/config/scenario.h"
#include "io/yaml_reader.h"
#include "methods/method.h"
#include "util/format.h"

namespace calibench {
namespace {

std::string Number(double v) {
  if (std::isnan(v)) return "–";
  if (std::isinf(v)) return v > 0 ? "`.inf`" : "`-.inf`";
  return FormatNumber(v, 10);
}

std::string Code(const std::string& s) { return s.empty() ? "\"\"" : "`" + s + "`"; }

std::string Vector(const Eigen::Vector3d& v) {
  if (!v.allFinite()) return "–";
  return "`[" + FormatNumber(v[0], 10) + ", " + FormatNumber(v[1], 10) + ", " +
         FormatNumber(v[2], 10) + "]`";
}

std::string OneOf(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& n : names) text += (text.empty() ? "" : " \\| ") + Code(n);
  return text;
}

struct Row {
  std::string key, type, default_value;
  std::string unit, doc;
};

// The table of a mapping's keys or of a method type's options.
std::string Table(const std::vector<Row>& rows) {
  std::ostringstream out;
  out << "| key | type | default | unit | meaning |\n|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    out << "| `" << r.key << "` | " << r.type << " | " << r.default_value << " | "
        << (r.unit.empty() ? "–" : r.unit) << " | " << r.doc << " |\n";
  }
  return out.str();
}

// One mapping's table, then the tables of its nested mappings (headings `path`).
class DocVisitor final : public FieldVisitor {
 public:
  DocVisitor(std::string path, int level) : path_(std::move(path)), level_(level) {}
  bool Reads() const override { return true; }

  void Field(const FieldSpec& f, double* v) override { Add(f, "number", Number(*v)); }
  void Field(const FieldSpec& f, int* v) override { Add(f, "integer", std::to_string(*v)); }
  void Field(const FieldSpec& f, uint64_t* v) override {
    Add(f, "integer ≥ 0", std::to_string(*v));
  }
  void Field(const FieldSpec& f, bool* v) override { Add(f, "bool", *v ? "true" : "false"); }
  void Field(const FieldSpec& f, std::string* v) override { Add(f, "string", Code(*v)); }
  void Field(const FieldSpec& f, std::string* v, const Choices& choices) override {
    Add(f,
        choices.names.size() > 8 ? "name (" + Code(choices.names.front()) + ", ...)"
                                 : OneOf(choices.names),
        v->empty() ? "none" : Code(*v));
  }
  void Field(const FieldSpec& f, Eigen::Vector3d* v) override { Add(f, "`[x, y, z]`", Vector(*v)); }
  void Field(const FieldSpec& f, Eigen::Matrix3d* v) override {
    Add(f, "3×3 list of rows", v->isIdentity() ? "identity" : "–");
  }
  void Field(const FieldSpec& f, std::vector<Eigen::Vector3d>*) override {
    Add(f, "list of `[x, y, z]`", "–");
  }
  void Field(const FieldSpec& f, int* first, int* second) override {
    Add(f, "`[width, height]`",
        "`[" + std::to_string(*first) + ", " + std::to_string(*second) + "]`");
  }
  void Section(const FieldSpec& f, const SectionOps& ops) override {
    Add(f, "mapping", "below");
    Nested(f.key, ops.visit);
  }
  void List(const FieldSpec& f, const ListOps& ops) override {
    Add(f, "list of mappings", "–");
    Nested(f.key, [&ops](FieldVisitor& w) {
      ops.resize(1);
      ops.visit(0, w);
    });
  }
  void Field(const FieldSpec& f, PointsConfig* v) override {
    Add(f, "mapping", "below");
    Nested(f.key, [v](FieldVisitor& w) { Visit(w, *v); });
  }
  void Field(const FieldSpec& f, std::vector<MethodInstance>*) override {
    Add(f, "list or mapping", "one instance per type; `adaptive` enabled");
  }
  void Exclusive(const char* key, const std::vector<const char*>&, const char* reason) override {
    notes_.push_back("With `" + std::string(key) + "`: " + reason + ".");
  }
  void Refused(const char* key, const char* reason) override {
    notes_.push_back("`" + std::string(key) + "` is refused: " + reason + ".");
  }

  std::string Text(const std::string& doc) const {
    std::ostringstream out;
    out << std::string(level_, '#') << " " << path_ << "\n\n";
    if (!doc.empty()) out << doc << "\n\n";
    out << Table(rows_);
    for (const std::string& n : notes_) out << "\n" << n << "\n";
    out << "\n" << nested_;
    return out.str();
  }

 private:
  void Add(const FieldSpec& f, const std::string& type, const std::string& default_value) {
    const std::string constrained = *f.constraint ? type + " " + f.constraint : type;
    rows_.push_back(
        {f.key, constrained, (f.flags & kRequired) ? "required" : default_value, f.unit, f.doc});
    docs_.emplace_back(f.key, f.doc);
  }
  void Nested(const std::string& key, const std::function<void(FieldVisitor&)>& visit) {
    const std::string path = path_ == "scenario" ? key : path_ + "." + key;
    DocVisitor child(path, std::min(level_ + 1, 4));
    visit(child);
    std::string doc;
    for (const auto& [k, d] : docs_)
      if (k == key) doc = d;
    nested_ += child.Text(doc);
  }

  std::string path_;
  int level_;
  std::vector<Row> rows_;
  std::vector<std::pair<std::string, std::string>> docs_;
  std::vector<std::string> notes_;
  std::string nested_;
};

// A method type's options, from its VisitOptions: each declaration's key, unit and doc, and the
// default (the value a new instance holds).
class OptionDoc final : public OptionVisitor {
 public:
  std::vector<Row> rows;
  void Field(const OptionSpec& o, double* v) override { Add(o, "number", Number(*v)); }
  void Field(const OptionSpec& o, int* v) override { Add(o, "integer", std::to_string(*v)); }
  void Field(const OptionSpec& o, long* v) override { Add(o, "integer", std::to_string(*v)); }
  void Field(const OptionSpec& o, bool* v) override { Add(o, "bool", *v ? "true" : "false"); }
  void Field(const OptionSpec& o, std::string* v,
             const std::vector<std::string>& choices) override {
    Add(o, choices.empty() ? "instance or type name" : OneOf(choices), Code(*v));
  }
  void Field(const OptionSpec& o, LensModel* v) override {
    Add(o, "lens model", Code(ToString(*v)));
  }
  void Field(const OptionSpec& o, CameraSpec*) override {
    Add(o, "camera mapping (as `truth`)", "–");
  }
  void FieldOrAll(const OptionSpec& o, double* v) override {
    Add(o, "number or `all`", std::isinf(*v) ? "`all`" : Number(*v));
  }

 private:
  void Add(const OptionSpec& o, const std::string& type, const std::string& default_value) {
    rows.push_back({o.key, type, default_value, o.unit, o.doc});
  }
};

}  // namespace

std::string MethodTypeReference(const MethodType& type) {
  const std::unique_ptr<Method> method = type.create();
  OptionDoc doc;
  method->VisitOptions(&doc);
  return "**" + type.name + "** (" + (type.enabled_by_default ? "enabled" : "disabled") +
         " by default): " + type.description + ".\n\n" + Table(doc.rows);
}

bool MethodsReference(const std::string& type, std::string* text, std::string* why) {
  std::string out;
  for (const MethodType& t : MethodTypes()) {
    if (!type.empty() && t.name != type) continue;
    out += (out.empty() ? "" : "\n") + MethodTypeReference(t);
  }
  if (!out.empty()) {
    *text = out;
    return true;
  }
  std::vector<std::string> names;
  for (const MethodType& t : MethodTypes()) names.push_back(t.name);
  const std::string best = config_internal::ClosestName(type, names);
  if (why) {
    *why = "unknown method type '" + type + "'" +
           (best.empty() ? "" : " (did you mean '" + best + "'?)") +
           "; registered types: " + MethodTypeNames();
  }
  return false;
}

std::string ConfigurationReference() {
  ScenarioConfig defaults;
  DocVisitor scenario("scenario", 2);
  Visit(scenario, defaults);
  std::ostringstream out;
  out << scenario.Text(
      "The keys of `scenario:` (and of an inline scenario of `scenarios:`). Defaults are the "
      "values a key takes when no file sets it.");
  out << "### methods\n\n"
         "Each type's options, from its `VisitOptions` ([methods.md](methods.md) explains "
         "them). Instance keys and the two forms of `methods:` are described below the "
         "generated part.\n\n";
  for (const MethodType& t : MethodTypes()) out << MethodTypeReference(t) << "\n";
  std::string text = out.str();
  while (text.size() > 1 && text[text.size() - 1] == '\n' && text[text.size() - 2] == '\n') {
    text.pop_back();
  }
  return text;
}

}  // namespace calibench
