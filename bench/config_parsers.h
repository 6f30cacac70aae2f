// Parsers of scenario sections shared by the config I/O files (internal; includes yaml-cpp).
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "bench/scenario.h"
#include "bench/yaml_reader.h"

namespace calibench {
namespace config_internal {

// {family, tag_rows, tag_cols, tag_size_m, tag_spacing, first_id, origin: [3], rpy_deg: [3]}.
void ParseAprilGrid(const Reader& r, const YAML::Node& node, const std::string& field,
                    AprilGrid* grid);
// rendering: {supersample, blur_sigma_px, noise_sigma_gray, background_gray, black_gray,
//             white_gray, threads, refine_corners,
//             detector: {quad_decimate, quad_sigma, refine_edges, decode_sharpening, threads,
//                        max_hamming}}
void ParseRendering(const Reader& r, const YAML::Node& node, const std::string& field,
                    RenderedSourceOptions* options);

}  // namespace config_internal
}  // namespace calibench
