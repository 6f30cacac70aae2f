// Parsers of scenario sections shared by the config I/O files (internal; includes yaml-cpp).
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <string>
#include <vector>

#include "bench/scenario.h"
#include "bench/yaml_reader.h"

namespace calibench {
namespace config_internal {

// {family, tag_rows, tag_cols, tag_size_m, tag_spacing, first_id, origin: [3], rpy_deg: [3]};
// *rpy_deg gets the angles as written (0 when absent).
void ParseAprilGrid(const Reader& r, const YAML::Node& node, const std::string& field,
                    AprilGrid* grid, Eigen::Vector3d* rpy_deg);
// rendering: {supersample, blur_sigma_px, noise_sigma_gray, background_gray, black_gray,
//             white_gray, threads, refine_corners,
//             detector: {quad_decimate, quad_sigma, refine_edges, decode_sharpening, threads,
//                        max_hamming}}
void ParseRendering(const Reader& r, const YAML::Node& node, const std::string& field,
                    RenderedSourceOptions* options);

// One axis of `sweep:`: a dotted scenario field and its values (YAML nodes, any type).
struct SweepAxis {
  enum Family { kMeasurement, kAdaptive, kBatch, kAllMethods };
  std::string field;
  std::vector<std::string> path;  // field split at the dots; numeric parts index lists.
  std::vector<YAML::Node> values;
  // kMeasurement: changes the data (a new measurement point); otherwise only methods' settings.
  Family family = kMeasurement;
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
