// Writing the resolved configuration (config_io.h): every field explicit, re-loadable.
#include <yaml-cpp/yaml.h>

#include <cmath>

#include "bench/config/config_io.h"
#include "bench/config/config_parsers.h"
#include "metrics/tracking.h"

namespace calibench {
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
