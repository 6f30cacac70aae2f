// Parsers of scenario sections shared by the config I/O files (internal; includes yaml-cpp).
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <string>
#include <vector>

#include "bench/config/fields.h"
#include "bench/config/scenario.h"
#include "io/yaml_reader.h"

namespace calibench {
namespace config_internal {

// The YAML visitors of the declarations (fields.h, scenario_fields.cc; config_fields_io.cc).

// The keys `visit` declares (the "did you mean" list of its mapping).
std::vector<std::string> DeclaredKeys(const std::function<void(FieldVisitor&)>& visit);

// Reads the fields `visit` declares from the mapping `node` (unknown keys are errors naming the
// closest declared one); fields whose key is absent keep their values. `context` is the scenario
// the custom section (methods) is read into; null outside a scenario.
void ReadFields(const Reader& r, const YAML::Node& node, const std::string& field,
                const std::function<void(FieldVisitor&)>& visit, ScenarioConfig* context);

// Writes every field `visit` declares as a mapping (`flow`: on one line).
void WriteFields(YAML::Emitter& out, const std::function<void(FieldVisitor&)>& visit, bool flow,
                 const ScenarioConfig* context);

// Reads the fields present in `node` without checking its keys (the caller did).
class FieldReader final : public FieldVisitor {
 public:
  FieldReader(const Reader& r, const YAML::Node& node, std::string field, ScenarioConfig* context)
      : r_(r), node_(node), field_(std::move(field)), context_(context) {}
  bool Reads() const override { return true; }
  void Field(const FieldSpec& f, double* v) override;
  void Field(const FieldSpec& f, int* v) override;
  void Field(const FieldSpec& f, uint64_t* v) override;
  void Field(const FieldSpec& f, bool* v) override;
  void Field(const FieldSpec& f, std::string* v) override;
  void Field(const FieldSpec& f, std::string* v, const Choices& choices) override;
  void Field(const FieldSpec& f, Eigen::Vector3d* v) override;
  void Field(const FieldSpec& f, Eigen::Matrix3d* v) override;
  void Field(const FieldSpec& f, std::vector<Eigen::Vector3d>* v) override;
  void Field(const FieldSpec& f, int* first, int* second) override;
  void Section(const FieldSpec& f, const SectionOps& ops) override;
  void List(const FieldSpec& f, const ListOps& ops) override;
  void Field(const FieldSpec& f, PointsConfig* v) override;
  void Field(const FieldSpec& f, std::vector<MethodInstance>* v) override;
  void Check(const char* key, const std::function<bool(std::string*)>& ok) override;
  void Exclusive(const char* key, const std::vector<const char*>& others,
                 const char* reason) override;

 private:
  template <typename F>
  void At(const FieldSpec& f, F read) {
    if ((f.flags & kRequired) && (!node_[f.key].IsDefined() || node_[f.key].IsNull())) {
      r_.Fail(node_, Reader::Join(field_, f.key), "missing");
    }
    r_.If(node_, f.key, field_, read);
  }
  void Checked(const FieldSpec& f, const YAML::Node& n, const std::string& field, double value);

  const Reader& r_;
  YAML::Node node_;
  std::string field_;
  ScenarioConfig* context_;
};

// {intrinsics, R_C, x_C, allow_improper_rotation}: the truth and the adaptive initial guess
// (Visit(FieldVisitor&, CameraSpec&)).
void ParseCamera(const Reader& r, const YAML::Node& node, const std::string& field, CameraSpec* c);
void EmitCamera(YAML::Emitter& out, const CameraSpec& c);

// points: (config_io.cc) one of its forms, resolved into p->xyz (random: drawn in Finish).
void ParsePoints(const Reader& r, const YAML::Node& node, const std::string& field,
                 PointsConfig* p);
void EmitPoints(YAML::Emitter& out, const PointsConfig& p);

// `methods:` (config_methods.cc): a list of instances, or the map form applied onto s->methods.
void ParseMethods(const Reader& r, const YAML::Node& node, const std::string& field,
                  ScenarioConfig* s);
// The resolved list form of s.methods (every instance, every option).
void EmitMethods(YAML::Emitter& out, const ScenarioConfig& s);
// A sweep axis `methods.NAME...` must name an instance of the swept scenario.
void CheckSweptMethod(const Reader& r, const YAML::Node& at, const std::string& field,
                      const std::string& name, const ScenarioConfig& swept);

// One axis of `sweep:`: a dotted scenario field and its values (YAML nodes, any type).
// NOLINTNEXTLINE(bugprone-exception-escape): YAML::Node's copy may throw (bad_alloc), as any.
struct SweepAxis {
  std::string field;
  YAML::Node field_node;          // Where the axis names its field (for messages).
  std::vector<std::string> path;  // field split at the dots; numeric parts index lists.
  std::vector<YAML::Node> values;
  // "file:line:col" of each value as written (a range's values: the range), for messages.
  std::vector<std::string> where;
  // False: the axis changes the data (a new measurement point); true: only methods' options.
  bool methods_only = false;
};
// `sweep: [{field, values: [...]} | {field, range: {from, to, step | log_step}}, ...]`.
std::vector<SweepAxis> ParseSweep(const Reader& r, const YAML::Node& node);

struct SweepPointSpec {
  std::string name;          // sweep_name[field=value,...]
  YAML::Node override_node;  // A scenario mapping to apply on top of the swept scenario.
  SweepPoint point;
  // Per axis: its field and where the point's value is written (the override is built in
  // memory, so its nodes have no line; an error in it is placed at the value that caused it).
  std::vector<std::pair<std::string, std::string>> value_where;
};
// The cartesian product of the axes, measurement axes outermost and method axes fastest.
// `wholesale_section(key)` gives the points / motion / reference section in force (these replace
// a base's section as a whole, so an axis inside one must start from the whole section).
std::vector<SweepPointSpec> ExpandSweep(
    std::vector<SweepAxis> axes, const std::string& sweep_name,
    const std::function<YAML::Node(const std::string& key)>& wholesale_section);

}  // namespace config_internal
}  // namespace calibench
