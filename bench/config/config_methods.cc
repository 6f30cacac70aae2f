// Config I/O of `methods:` (config_io.h): the list form of named instances, the map form (one
// instance per type, name = type), and the YAML visitors through which each method type reads and
// writes its own options (methods/method.h: the methods never see YAML).
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "bench/config/config_parsers.h"
#include "methods/options.h"

namespace calibench {
namespace config_internal {
namespace {

// Collects the option keys of a method (the allowed keys of its entry).
class KeyCollector final : public OptionVisitor {
 public:
  void Field(const OptionSpec& spec, double*) override { keys.emplace_back(spec.key); }
  void Field(const OptionSpec& spec, int*) override { keys.emplace_back(spec.key); }
  void Field(const OptionSpec& spec, long*) override { keys.emplace_back(spec.key); }
  void Field(const OptionSpec& spec, bool*) override { keys.emplace_back(spec.key); }
  void Field(const OptionSpec& spec, std::string*, const std::vector<std::string>&) override {
    keys.emplace_back(spec.key);
  }
  void Field(const OptionSpec& spec, LensModel*) override { keys.emplace_back(spec.key); }
  void Field(const OptionSpec& spec, CameraSpec*) override { keys.emplace_back(spec.key); }
  void FieldOrAll(const OptionSpec& spec, double*) override { keys.emplace_back(spec.key); }
  std::vector<std::string> keys;
};

// Reads the options present in `node`; errors name the file, line and field.
class YamlOptionReader final : public OptionVisitor {
 public:
  YamlOptionReader(const Reader& r, const YAML::Node& node, std::string field)
      : r_(r), node_(node), field_(std::move(field)) {}
  void Field(const OptionSpec& spec, double* v) override { r_.Set(node_, spec.key, field_, v); }
  void Field(const OptionSpec& spec, int* v) override { r_.Set(node_, spec.key, field_, v); }
  void Field(const OptionSpec& spec, long* v) override {
    r_.If(node_, spec.key, field_,
          [&](const YAML::Node& n, const std::string& f) { *v = r_.Integer(n, f); });
  }
  void Field(const OptionSpec& spec, bool* v) override { r_.Set(node_, spec.key, field_, v); }
  void Field(const OptionSpec& spec, std::string* v,
             const std::vector<std::string>& choices) override {
    r_.If(node_, spec.key, field_, [&](const YAML::Node& n, const std::string& f) {
      *v = choices.empty() ? r_.String(n, f) : r_.Choice(n, f, choices);
    });
  }
  void Field(const OptionSpec& spec, LensModel* v) override {
    r_.If(node_, spec.key, field_, [&](const YAML::Node& n, const std::string& f) {
      ParseLensModel(r_.Choice(n, f, LensModelNames()), v);
    });
  }
  void Field(const OptionSpec& spec, CameraSpec* v) override {
    r_.If(node_, spec.key, field_,
          [&](const YAML::Node& n, const std::string& f) { ParseCamera(r_, n, f, v); });
  }
  void FieldOrAll(const OptionSpec& spec, double* v) override {
    r_.If(node_, spec.key, field_, [&](const YAML::Node& n, const std::string& f) {
      *v = n.IsScalar() && n.Scalar() == "all" ? std::numeric_limits<double>::infinity()
                                               : r_.Double(n, f);
    });
  }

 private:
  const Reader& r_;
  const YAML::Node& node_;
  std::string field_;
};

// Writes every option as `key: value` into the open map of `out`.
class YamlOptionWriter final : public OptionVisitor {
 public:
  explicit YamlOptionWriter(YAML::Emitter* out) : out_(*out) {}
  void Field(const OptionSpec& spec, double* v) override {
    out_ << YAML::Key << spec.key << YAML::Value << *v;
  }
  void Field(const OptionSpec& spec, int* v) override {
    out_ << YAML::Key << spec.key << YAML::Value << *v;
  }
  void Field(const OptionSpec& spec, long* v) override {
    out_ << YAML::Key << spec.key << YAML::Value << *v;
  }
  void Field(const OptionSpec& spec, bool* v) override {
    out_ << YAML::Key << spec.key << YAML::Value << *v;
  }
  void Field(const OptionSpec& spec, std::string* v, const std::vector<std::string>&) override {
    out_ << YAML::Key << spec.key << YAML::Value << *v;
  }
  void Field(const OptionSpec& spec, LensModel* v) override {
    out_ << YAML::Key << spec.key << YAML::Value << ToString(*v);
  }
  void Field(const OptionSpec& spec, CameraSpec* v) override {
    out_ << YAML::Key << spec.key << YAML::Value;
    EmitCamera(out_, *v);
  }
  void FieldOrAll(const OptionSpec& spec, double* v) override {
    out_ << YAML::Key << spec.key << YAML::Value;
    if (std::isinf(*v)) {
      out_ << "all";
    } else {
      out_ << *v;
    }
  }

 private:
  YAML::Emitter& out_;
};

// Applies one entry (a mapping of instance keys and options) to `instance`.
enum class EntryForm { kList, kMap, kNewInMap };  // kNewInMap: `NAME: {type: T, ...}`.

void ApplyEntry(const Reader& r, const YAML::Node& node, const std::string& field, EntryForm form,
                MethodInstance* instance) {
  if (node.IsNull()) return;  // `dlt:` with nothing after it: no change.
  KeyCollector keys;
  instance->method->VisitOptions(&keys);
  std::vector<std::string> allowed = {"enabled", "convergence_tol"};
  if (form == EntryForm::kList) allowed.insert(allowed.begin(), {"name", "type"});
  if (form == EntryForm::kNewInMap) allowed.insert(allowed.begin(), "type");
  allowed.insert(allowed.end(), keys.keys.begin(), keys.keys.end());
  r.CheckKeys(node, field, allowed);
  r.Set(node, "enabled", field, &instance->enabled);
  r.If(node, "convergence_tol", field, [&](const YAML::Node& n, const std::string& f) {
    instance->convergence_tol = r.Double(n, f);
    if (!(instance->convergence_tol > 0)) r.Fail(n, f, "must be > 0");
  });
  YamlOptionReader reader(r, node, field);
  instance->method->VisitOptions(&reader);
  std::string why;
  if (!instance->method->Check(&why)) r.Fail(node, field, why);
}

// A type name, or why not (naming the registered types).
bool CheckTypeName(const Reader& r, const YAML::Node& node, const std::string& field,
                   std::string* type) {
  *type = r.String(node, field);
  if (FindMethodType(*type) != nullptr) return true;
  r.Fail(node, field,
         "unknown method type '" + *type + "'; registered types: " + MethodTypeNames());
  return false;
}

// An instance name, or a refusal saying what a name may hold.
void CheckInstanceName(const Reader& r, const YAML::Node& at, const std::string& field,
                       const std::string& name) {
  if (name.empty() || name.find_first_of(".[],;= ") != std::string::npos) {
    r.Fail(at, field,
           "'" + name + "': an instance name must be non-empty, without spaces or . [ ] , ; =");
  }
}

std::string InstanceNames(const ScenarioConfig& s) {
  std::string names;
  for (const MethodInstance& m : s.methods) names += (names.empty() ? "" : ", ") + m.name;
  return names.empty() ? "(none)" : names;
}

void ParseList(const Reader& r, const YAML::Node& node, const std::string& field,
               ScenarioConfig* s) {
  std::vector<MethodInstance> instances;
  for (size_t i = 0; i < node.size(); ++i) {
    const YAML::Node entry = node[i];
    const std::string f = field + "[" + std::to_string(i) + "]";
    r.ExpectMap(entry, f);
    if (!entry["type"].IsDefined()) {
      r.Fail(entry, f,
             "missing 'type': every instance names its method type (" + MethodTypeNames() + ")");
    }
    std::string type;
    CheckTypeName(r, entry["type"], f + ".type", &type);
    std::string name = type;
    r.Set(entry, "name", f, &name);
    const YAML::Node at = entry["name"].IsDefined() ? entry["name"] : entry;
    CheckInstanceName(r, at, f + ".name", name);
    for (size_t j = 0; j < instances.size(); ++j) {
      if (instances[j].name == name) {
        std::string reason = "'" + name + "' is already the name of ";
        reason += field + "[" + std::to_string(j) + "]";
        reason += ": instance names key the result rows and must be unique";
        r.Fail(at, f + ".name", reason);
      }
    }
    MethodInstance instance = MethodInstance::OfType(type, name);
    instance.enabled = true;  // Listing an instance runs it unless it says otherwise.
    ApplyEntry(r, entry, f, EntryForm::kList, &instance);
    instances.push_back(std::move(instance));
  }
  s->methods = std::move(instances);
}

void ParseMap(const Reader& r, const YAML::Node& node, const std::string& field,
              ScenarioConfig* s) {
  std::vector<std::string> allowed;
  for (const MethodInstance& m : s->methods) allowed.push_back(m.name);
  for (const MethodType& t : MethodTypes()) {
    if (std::find(allowed.begin(), allowed.end(), t.name) == allowed.end()) {
      allowed.push_back(t.name);
    }
  }
  // A key naming no instance and no type adds an instance when its entry gives a type.
  std::vector<std::string> added;
  for (const auto& kv : node) {
    const std::string key = kv.first.Scalar();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    if (!kv.second.IsMap() || !kv.second["type"].IsDefined()) continue;  // CheckKeys refuses it.
    const std::string f = Reader::Join(field, key);
    std::string type;
    CheckTypeName(r, kv.second["type"], f + ".type", &type);
    CheckInstanceName(r, kv.first, f, key);
    MethodInstance instance = MethodInstance::OfType(type, key);
    instance.enabled = true;  // As a listed instance.
    ApplyEntry(r, kv.second, f, EntryForm::kNewInMap, &instance);
    s->methods.push_back(std::move(instance));
    allowed.push_back(key);
    added.push_back(key);
  }
  r.CheckKeys(node, field, allowed);
  for (const auto& kv : node) {
    const std::string key = kv.first.Scalar();
    const std::string f = Reader::Join(field, key);
    if (std::find(added.begin(), added.end(), key) != added.end()) continue;
    if (kv.second.IsMap() && kv.second["type"].IsDefined()) {
      const MethodInstance* existing = s->FindMethod(key);
      r.Fail(kv.second["type"], f + ".type",
             "'" + key + "' is already " +
                 (existing ? "an instance of type " + existing->type : "a method type") +
                 "; `type:` in the map form only adds a new instance");
    }
    auto instance_named = [&](const std::string& name) {
      if (MethodInstance* found = s->FindMethod(name)) return found;
      s->methods.push_back(MethodInstance::OfType(name, name));  // A type name (CheckKeys).
      return &s->methods.back();
    };
    MethodInstance* instance = instance_named(key);
    ApplyEntry(r, kv.second, f, EntryForm::kMap, instance);
    if (instance->name != instance->type) continue;
    for (const std::string& companion : FindMethodType(instance->type)->companions) {
      ApplyEntry(r, kv.second, f, EntryForm::kMap, instance_named(companion));
    }
  }
}

}  // namespace

void ParseMethods(const Reader& r, const YAML::Node& node, const std::string& field,
                  ScenarioConfig* s) {
  if (node.IsSequence()) return ParseList(r, node, field, s);
  if (node.IsMap()) return ParseMap(r, node, field, s);
  r.Fail(node, field,
         "expected a list of instances [{name, type, ...}] or a mapping {NAME: {options}}");
}

void CheckSweptMethod(const Reader& r, const YAML::Node& at, const std::string& field,
                      const std::string& name, const ScenarioConfig& swept) {
  if (swept.FindMethod(name) != nullptr) return;
  r.Fail(at, field,
         "no method instance named '" + name + "' in scenario '" + swept.name +
             "'; its instances: " + InstanceNames(swept));
}

void EmitMethods(YAML::Emitter& out, const ScenarioConfig& s) {
  out << YAML::BeginSeq;
  for (const MethodInstance& m : s.methods) {
    out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << m.name << YAML::Key << "type"
        << YAML::Value << m.type << YAML::Key << "enabled" << YAML::Value << m.enabled << YAML::Key
        << "convergence_tol" << YAML::Value << m.convergence_tol;
    YamlOptionWriter writer(&out);
    VisitOptionsReadOnly(*m.method, &writer);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
}

}  // namespace config_internal
}  // namespace calibench
