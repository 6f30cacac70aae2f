// Writing the resolved configuration (config_io.h): every field explicit, re-loadable.
#include <yaml-cpp/yaml.h>

#include <cmath>

#include "bench/config/config_io.h"
#include "bench/config/config_parsers.h"
#include "metrics/tracking.h"

namespace calibench {
namespace {

void EmitVector(YAML::Emitter& out, const Eigen::Vector3d& v) {
  out << YAML::Flow << YAML::BeginSeq << v[0] << v[1] << v[2] << YAML::EndSeq;
}

}  // namespace

// The resolved points: the boards, the grids, or the list (a preset or a box as its points).
void config_internal::EmitPoints(YAML::Emitter& out, const PointsConfig& p) {
  PointsConfig copy = p;
  const bool boards = !copy.boards.empty(), grids = !copy.aprilgrids.empty();
  config_internal::WriteFields(
      out,
      [&](FieldVisitor& v) {
        if (boards) {
          VisitList(v, {"boards"}, &copy.boards);
        } else if (grids) {
          VisitList(v, {"aprilgrids"}, &copy.aprilgrids);
        } else {
          v.Field({"list"}, &copy.xyz);
        }
      },
      false, nullptr);
}

void config_internal::EmitChanges(YAML::Emitter& out,
                                  const std::vector<CalibrationChange>& changes) {
  out << YAML::BeginSeq;
  for (const CalibrationChange& e : changes) {
    const bool step = e.kind == CalibrationChange::Kind::kStep;
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "kind" << YAML::Value
        << (step ? "step" : "ramp");
    if (step) {
      out << YAML::Key << "at_s" << YAML::Value << e.from_s;
    } else {
      out << YAML::Key << "from_s" << YAML::Value << e.from_s << YAML::Key << "to_s" << YAML::Value
          << e.to_s;
    }
    out << YAML::Key << "rpy_deg" << YAML::Value;
    EmitVector(out, e.rpy_deg);
    out << YAML::Key << "x_m" << YAML::Value;
    EmitVector(out, e.x_m);
    const std::pair<const char*, double> deltas[] = {{"fku_px", e.fku_px},
                                                     {"fkv_px", e.fkv_px},
                                                     {"u0_px", e.u0_px},
                                                     {"v0_px", e.v0_px},
                                                     {"phi_deg", e.phi_deg}};
    for (const auto& [key, v] : deltas) out << YAML::Key << key << YAML::Value << v;
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
}

std::string ResolvedYaml(const RunConfig& config) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::Comment("calibench resolved configuration: every default filled in");
  out << YAML::BeginMap << YAML::Key << "scenarios" << YAML::Value << YAML::BeginSeq;
  for (const ScenarioConfig& s : config.scenarios) {
    ScenarioConfig copy = s;  // Visit takes a mutable struct; the writer only reads it.
    config_internal::WriteFields(
        out, [&copy](FieldVisitor& v) { Visit(v, copy); }, false, &copy);
  }
  out << YAML::EndSeq << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace calibench
