// The YAML reader and writer of the declared fields (fields.h, scenario_fields.cc): every section
// of the scenario is read and written through these two visitors.
#include <yaml-cpp/yaml.h>

#include <cmath>

#include "bench/config/config_parsers.h"
#include "io/yaml_reader.h"

namespace calibench {
namespace config_internal {
namespace {

// The declared keys (and the refused ones with their reasons) of a mapping.
class KeyCollector final : public SpecVisitor {
 public:
  std::vector<std::string> keys;
  std::vector<std::pair<std::string, std::string>> refused;
  void Spec(const FieldSpec& f) override { keys.emplace_back(f.key); }
  void Refused(const char* key, const char* reason) override { refused.emplace_back(key, reason); }
};

void EmitVector(YAML::Emitter& out, const Eigen::Vector3d& v) {
  out << YAML::Flow << YAML::BeginSeq << v[0] << v[1] << v[2] << YAML::EndSeq;
}

class FieldWriter final : public FieldVisitor {
 public:
  FieldWriter(YAML::Emitter& out, const ScenarioConfig* context) : out_(out), context_(context) {}
  void Field(const FieldSpec& f, double* v) override {
    if (Key(f, std::isnan(*v))) out_ << *v;
  }
  void Field(const FieldSpec& f, int* v) override {
    if (Key(f, *v == 0)) out_ << *v;
  }
  void Field(const FieldSpec& f, uint64_t* v) override {
    if (Key(f, *v == 0)) out_ << *v;
  }
  void Field(const FieldSpec& f, bool* v) override {
    if (Key(f, !*v)) out_ << *v;
  }
  void Field(const FieldSpec& f, std::string* v) override {
    if (Key(f, v->empty())) out_ << *v;
  }
  void Field(const FieldSpec& f, std::string* v, const Choices& choices) override {
    if (Key(f, v->empty() || (choices.first_is_unset && *v == choices.names.front()))) out_ << *v;
  }
  void Field(const FieldSpec& f, Eigen::Vector3d* v) override {
    if (Key(f, !v->allFinite())) EmitVector(out_, *v);
  }
  void Field(const FieldSpec& f, Eigen::Matrix3d* v) override {
    if (!Key(f, false)) return;
    out_ << YAML::Flow << YAML::BeginSeq;
    for (int r = 0; r < 3; ++r) EmitVector(out_, v->row(r).transpose());
    out_ << YAML::EndSeq;
  }
  void Field(const FieldSpec& f, std::vector<Eigen::Vector3d>* v) override {
    if (!Key(f, v->empty())) return;
    out_ << YAML::BeginSeq;
    for (const Eigen::Vector3d& p : *v) EmitVector(out_, p);
    out_ << YAML::EndSeq;
  }
  void Field(const FieldSpec& f, int* first, int* second) override {
    if (Key(f, false)) out_ << YAML::Flow << YAML::BeginSeq << *first << *second << YAML::EndSeq;
  }
  void Section(const FieldSpec& f, const SectionOps& ops) override {
    if (!ops.written || !Key(f, false)) return;
    WriteFields(out_, ops.visit, ops.flow, context_);
  }
  void List(const FieldSpec& f, const ListOps& ops) override {
    if (!Key(f, ops.size == 0)) return;
    out_ << YAML::BeginSeq;
    for (size_t i = 0; i < ops.size; ++i) {
      WriteFields(
          out_, [&](FieldVisitor& w) { ops.visit(i, w); }, ops.flow_items, context_);
    }
    out_ << YAML::EndSeq;
  }
  void Field(const FieldSpec& f, PointsConfig* v) override {
    if (Key(f, false)) EmitPoints(out_, *v);
  }
  void Field(const FieldSpec& f, std::vector<MethodInstance>*) override {
    if (Key(f, false)) EmitMethods(out_, *context_);
  }

 private:
  // Writes the key of a field that is written; false when it is not.
  bool Key(const FieldSpec& f, bool unset) {
    if ((f.flags & kNotWritten) || ((f.flags & kOmitUnset) && unset)) return false;
    out_ << YAML::Key << f.key << YAML::Value;
    return true;
  }

  YAML::Emitter& out_;
  const ScenarioConfig* context_;
};

}  // namespace

std::vector<std::string> DeclaredKeys(const std::function<void(FieldVisitor&)>& visit) {
  KeyCollector keys;
  visit(keys);
  return keys.keys;
}

void ReadFields(const Reader& r, const YAML::Node& node, const std::string& field,
                const std::function<void(FieldVisitor&)>& visit, ScenarioConfig* context) {
  KeyCollector keys;
  visit(keys);
  if (node.IsMap()) {
    for (const auto& [key, reason] : keys.refused) {
      if (node[key]) r.Fail(node[key], Reader::Join(field, key), reason);
    }
  }
  r.CheckKeys(node, field, keys.keys);
  FieldReader reader(r, node, field, context);
  visit(reader);
}

void WriteFields(YAML::Emitter& out, const std::function<void(FieldVisitor&)>& visit, bool flow,
                 const ScenarioConfig* context) {
  if (flow) out << YAML::Flow;
  out << YAML::BeginMap;
  FieldWriter writer(out, context);
  visit(writer);
  out << YAML::EndMap;
}

void FieldReader::Checked(const FieldSpec& f, const YAML::Node& n, const std::string& field,
                          double value) {
  std::string why;
  if (f.check != nullptr && !f.check(value, &why)) r_.Fail(n, field, why);
}

void FieldReader::Field(const FieldSpec& f, double* v) {
  At(f, [&](const YAML::Node& n, const std::string& g) {
    *v = r_.Double(n, g);
    Checked(f, n, g, *v);
  });
}
void FieldReader::Field(const FieldSpec& f, int* v) {
  At(f, [&](const YAML::Node& n, const std::string& g) {
    Checked(f, n, g,
            static_cast<double>(r_.Integer(n, g)));  // The check's reason before the range.
    *v = r_.Int(n, g);
  });
}
void FieldReader::Field(const FieldSpec& f, uint64_t* v) {
  At(f, [&](const YAML::Node& n, const std::string& g) {
    *v = r_.Unsigned(n, g);
    Checked(f, n, g, static_cast<double>(*v));
  });
}
void FieldReader::Field(const FieldSpec& f, bool* v) {
  At(f, [&](const YAML::Node& n, const std::string& g) { *v = r_.Bool(n, g); });
}
void FieldReader::Field(const FieldSpec& f, std::string* v) {
  At(f, [&](const YAML::Node& n, const std::string& g) { *v = r_.String(n, g); });
}
void FieldReader::Field(const FieldSpec& f, std::string* v, const Choices& choices) {
  At(f, [&](const YAML::Node& n, const std::string& g) {
    const std::string value = r_.String(n, g);
    for (const std::string& c : choices.names) {
      if (c == value) {
        *v = value;
        return;
      }
    }
    r_.Fail(n, g, NotOneOf(value, choices.names, choices.noun));
  });
}
void FieldReader::Field(const FieldSpec& f, Eigen::Vector3d* v) {
  At(f, [&](const YAML::Node& n, const std::string& g) { *v = r_.Vector3(n, g); });
}
void FieldReader::Field(const FieldSpec& f, Eigen::Matrix3d* v) {
  At(f, [&](const YAML::Node& n, const std::string& g) { *v = r_.Matrix3(n, g); });
}
void FieldReader::Field(const FieldSpec& f, std::vector<Eigen::Vector3d>* v) {
  At(f, [&](const YAML::Node& n, const std::string& g) {
    if (!n.IsSequence() || n.size() == 0) {
      r_.Fail(n, g, "expected a non-empty list of [x, y, z] points");
    }
    v->clear();
    for (size_t i = 0; i < n.size(); ++i) {
      v->push_back(r_.Vector3(n[i], g + "[" + std::to_string(i) + "]"));
    }
  });
}
void FieldReader::Field(const FieldSpec& f, int* first, int* second) {
  At(f, [&](const YAML::Node& n, const std::string& g) {
    if (!n.IsSequence() || n.size() != 2) r_.Fail(n, g, "expected a list of 2 integers");
    *first = r_.Int(n[0], g + "[0]");
    *second = r_.Int(n[1], g + "[1]");
  });
}
void FieldReader::Section(const FieldSpec& f, const SectionOps& ops) {
  At(f, [&](const YAML::Node& n, const std::string& g) {
    if (ops.reset) ops.reset();
    ReadFields(r_, n, g, ops.visit, context_);
  });
}
void FieldReader::List(const FieldSpec& f, const ListOps& ops) {
  At(f, [&](const YAML::Node& n, const std::string& g) {
    if (!n.IsSequence() || (n.size() == 0 && !ops.allow_empty)) {
      r_.Fail(n, g, ops.allow_empty ? "expected a list of mappings" : "expected a non-empty list");
    }
    ops.resize(0);
    ops.resize(n.size());
    for (size_t i = 0; i < n.size(); ++i) {
      const std::string item = g + "[" + std::to_string(i) + "]";
      r_.ExpectMap(n[i], item);
      ReadFields(
          r_, n[i], item, [&](FieldVisitor& w) { ops.visit(i, w); }, context_);
      if (ops.located) ops.located(i, r_.Where(n[i]));
    }
  });
}
void FieldReader::Field(const FieldSpec& f, PointsConfig* v) {
  At(f, [&](const YAML::Node& n, const std::string& g) { ParsePoints(r_, n, g, v); });
}
void FieldReader::Field(const FieldSpec& f, std::vector<MethodInstance>*) {
  At(f, [&](const YAML::Node& n, const std::string& g) { ParseMethods(r_, n, g, context_); });
}
void FieldReader::Check(const char* key, const std::function<bool(std::string*)>& ok) {
  std::string why;
  if (ok(&why)) return;
  const bool at_key = key != nullptr && node_[key].IsDefined();
  r_.Fail(at_key ? node_[key] : node_, key ? Reader::Join(field_, key) : field_, why);
}
void FieldReader::Exclusive(const char* key, const std::vector<const char*>& others,
                            const char* reason) {
  if (!node_[key].IsDefined()) return;
  for (const char* other : others) {
    if (node_[other].IsDefined()) r_.Fail(node_[other], Reader::Join(field_, other), reason);
  }
}

void ParseCamera(const Reader& r, const YAML::Node& node, const std::string& field, CameraSpec* c) {
  ReadFields(
      r, node, field, [c](FieldVisitor& v) { Visit(v, *c); }, nullptr);
}

void EmitCamera(YAML::Emitter& out, const CameraSpec& c) {
  CameraSpec copy = c;
  WriteFields(
      out, [&copy](FieldVisitor& v) { Visit(v, copy); }, false, nullptr);
}

}  // namespace config_internal
}  // namespace calibench
