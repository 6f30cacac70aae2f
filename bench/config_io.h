// Reading and writing scenario YAML. The only place that includes yaml-cpp.
//
// A scenario file:                          An entry point (runs several):
//   base: ../common.yaml   # optional         scenarios:
//   scenario:                                   - sim01.yaml        # path, relative to this file
//     name: sim07                               - {name: x, ...}    # or an inline scenario
//     case: moving_camera | fixed_camera
//     duration_s: 240, seed: 7, trials: 1
//     truth: {intrinsics: {fku_px, fkv_px, phi_deg, u0_px, v0_px, k1, k2},
//             R_C: [[..],[..],[..]], x_C: [x, y, z], allow_improper_rotation: false}
//     points: {preset: thesis, count: 5}  |  {list: [[x, y, z], ...]}
//             | {random: {count, min: [3], max: [3]}}   (uniform in the box, from the seed)
//             | {boards: [{rows, cols, spacing_m, origin: [3], rpy_deg: [3]}, ...]}  (a rig)
//             | {aprilgrids: [{family, tag_rows, tag_cols, tag_size_m, tag_spacing, first_id,
//                              origin: [3], rpy_deg: [3]}, ...]}  (AprilTag rig)
//     image_size: [640, 480]
//     motion: {preset: small}  |  {v_const, v_cos, v_sin, w_const, w_cos, w_sin: [3],
//              frequency_rad_s, frame: auto | body | world}
//     measurements: {detections: oracle | rendered, sample_rate_hz: 0, eval_rate_hz: 10,
//                    outside_image: fail | keep}   (oracle: a projection outside image_size)
//     noise: {point_sigma_m, pixel_sigma_px, hold_s, hold_frames}
//     rendering: {supersample, blur_sigma_px, noise_sigma_gray, ..., detector: {...}}
//     (config_parsers.h) methods: {adaptive: {enabled, alpha, gamma0, rtol, max_step_s,
//     initial_step_s, max_steps,
//               convergence_tol, initial: {intrinsics, R_C, x_C, allow_improper_rotation}},
//               dlt: {enabled, min_planarity_ratio},
//               zhang: {enabled, model, view_stride, max_views},
//               ceres: {enabled, init: dlt | zhang, model, estimate_skew, loss, loss_scale_px,
//                       max_iterations, autodiff}}
//     reference: {source, fku_px, fkv_px, phi_deg, u0_px, v0_px, x_C, theta_err_below}
//
// `base:` loads another scenario file first; this file's fields then override it (a `points`,
// `motion` or `reference` section replaces the base's as a whole). Unknown keys, wrong types and
// invalid values are errors of the form "FILE:LINE:COL: FIELD: REASON".
#pragma once

#include <string>
#include <vector>

#include "bench/scenario.h"

namespace calibench {

struct RunConfig {
  std::vector<ScenarioConfig> scenarios;
};

// Loads a scenario file or an entry point. On failure returns false and *why says file, line,
// column, field and reason.
bool LoadRunConfig(const std::string& path, RunConfig* config, std::string* why);
// Same, from YAML text (`virtual_path` names it in messages and anchors relative paths).
bool LoadRunConfigFromString(const std::string& yaml, const std::string& virtual_path,
                             RunConfig* config, std::string* why);

// The configuration with every default filled in, as an entry point with inline scenarios that
// LoadRunConfig reads back to the same values.
std::string ResolvedYaml(const RunConfig& config);

}  // namespace calibench
