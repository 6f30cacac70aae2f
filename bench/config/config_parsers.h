// Parsers of scenario sections shared by the config I/O files (internal; includes yaml-cpp).
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <string>
#include <vector>

#include "bench/config/scenario.h"
#include "bench/config/yaml_reader.h"

namespace calibench {
namespace config_internal {

// {intrinsics, R_C, x_C, allow_improper_rotation}: the truth and the adaptive initial guess. The
// truth's section may also hold `changes` (extra_keys), parsed by the caller.
void ParseCamera(const Reader& r, const YAML::Node& node, const std::string& field, CameraSpec* c,
                 const std::vector<std::string>& extra_keys = {});
// `changes`, when given, is written as the map's `changes` list.
void EmitCamera(YAML::Emitter& out, const CameraSpec& c,
                const std::vector<CalibrationChange>* changes = nullptr);

// `methods:` (config_methods.cc): a list of instances, or the map form applied onto s->methods.
void ParseMethods(const Reader& r, const YAML::Node& node, const std::string& field,
                  ScenarioConfig* s);
// The resolved list form of s.methods (every instance, every option).
void EmitMethods(YAML::Emitter& out, const ScenarioConfig& s);
// A sweep axis `methods.NAME...` must name an instance of the swept scenario.
void CheckSweptMethod(const Reader& r, const YAML::Node& at, const std::string& field,
                      const std::string& name, const ScenarioConfig& swept);

// {family, tag_rows, tag_cols, tag_size_m, tag_spacing, first_id, black_tag_border (default 1),
//  corner_squares (default false), origin: [3], rpy_deg: [3]};
// *rpy_deg gets the angles as written (0 when absent).
void ParseAprilGrid(const Reader& r, const YAML::Node& node, const std::string& field,
                    AprilGrid* grid, Eigen::Vector3d* rpy_deg);
// rendering: {supersample, blur_sigma_px, blur_grid, noise_sigma_gray, background_gray, black_gray,
//             white_gray, threads, corner_refinement,
//             detector: {quad_decimate, quad_sigma, refine_edges, decode_sharpening, threads,
//                        max_hamming}}
void ParseRendering(const Reader& r, const YAML::Node& node, const std::string& field,
                    RenderedSourceOptions* options);

// One axis of `sweep:`: a dotted scenario field and its values (YAML nodes, any type).
struct SweepAxis {
  std::string field;
  YAML::Node field_node;          // Where the axis names its field (for messages).
  std::vector<std::string> path;  // field split at the dots; numeric parts index lists.
  std::vector<YAML::Node> values;
  // False: the axis changes the data (a new measurement point); true: only methods' options.
  bool methods_only = false;
};
// `sweep: [{field, values: [...]} | {field, range: {from, to, step | log_step}}, ...]`.
std::vector<SweepAxis> ParseSweep(const Reader& r, const YAML::Node& node);

struct SweepPointSpec {
  std::string name;          // sweep_name[field=value,...]
  YAML::Node override_node;  // A scenario mapping to apply on top of the swept scenario.
  SweepPoint point;
};
// The cartesian product of the axes, measurement axes outermost and method axes fastest.
// `wholesale_section(key)` gives the points / motion / reference section in force (these replace
// a base's section as a whole, so an axis inside one must start from the whole section).
std::vector<SweepPointSpec> ExpandSweep(
    std::vector<SweepAxis> axes, const std::string& sweep_name,
    const std::function<YAML::Node(const std::string& key)>& wholesale_section);

}  // namespace config_internal
}  // namespace calibench
