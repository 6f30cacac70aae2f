// Reading and writing scenario YAML. The only place that includes yaml-cpp.
//
// A scenario file:                          An entry point (runs several):
//   base: ../common.yaml   # optional         scenarios:
//   scenario:                                   - sim01.yaml        # path, relative to this file
//     name: sim07                               - {name: x, ...}    # or an inline scenario
//     case: moving_camera | fixed_camera
//     duration_s: 240, seed: 7, trials: 1
//     paired_sweep: false   # true: every sweep point runs the same trials (paired diagnostics)
//     truth: {intrinsics: {fku_px, fkv_px, phi_deg, u0_px, v0_px, k1, k2},
//             R_C: [[..],[..],[..]], x_C: [x, y, z], allow_improper_rotation: false}
//     points: {preset: thesis, count: 5}  |  {list: [[x, y, z], ...]}
//             | {random: {count, min: [3], max: [3]}}   (uniform in the box, from the seed)
//             | {boards: [{rows, cols, spacing_m, origin: [3], rpy_deg: [3]}, ...]}  (a rig)
//             | {aprilgrids: [{family, tag_rows, tag_cols, tag_size_m, tag_spacing, first_id,
//                              black_tag_border, corner_squares, origin: [3], rpy_deg: [3]},
//                             ...]}  (AprilTag rig; black_tag_border: 1 = AprilTag 3's layout,
//               the default; 2 = Kalibr's printed tags, rendered and detected with a 2-bit border;
//               corner_squares: false by default, true for Kalibr's squares; core/target.h)
//     image_size: [640, 480]
//     motion: {preset: small}  |  {v_const, v_cos, v_sin, w_const, w_cos, w_sin: [3],
//              frequency_rad_s, frame: auto | body | world}; either form may add
//              random_phase: true (each trial starts the profile at its own phase)
//     measurements: {detections: oracle | rendered, sample_rate_hz: 0, eval_rate_hz: 10,
//                    outside_image: fail | keep}   (oracle: a projection outside image_size)
//     noise: {point_sigma_m, pixel_sigma_px, hold_s, hold_frames, tag_radial_bias_px}
//     rendering: {supersample, blur_sigma_px, blur_grid (sub-pixels a side the blur is computed
//                 on; 0: automatic, core/render.h), noise_sigma_gray, ..., corner_refinement,
//                 min_border_distance_px, corner_error_clip_px, corner_error_part,
//                 corner_error_grid (diagnostics: detect/rendered_source.h), detector: {...}}
//     methods:                                   # named instances (methods/registry.h), in row
//       - {name: a100, type: adaptive, alpha: 100}   # order; keys: name (default: the type),
//       - {name: ceres, type: ceres, init: dlt}      # type, enabled (default true),
//                                                     # convergence_tol, the type's options
//     methods: {adaptive: {alpha: 100}, ceres: {enabled: true}}   # or the map form: one
//             # instance per type, name = type, enabled as the type says (adaptive only); a key
//             # may also name an existing instance, and `zhang:` configures zhang_handeye too;
//             # a new name with `type:` adds an instance: {twin: {type: ceres, init: zhang}}.
//       type options:  adaptive: alpha, gamma0, rtol, max_step_s, initial_step_s, max_steps,
//                                initial: {intrinsics, R_C, x_C, allow_improper_rotation}
//                      dlt: min_planarity_ratio
//                      zhang, zhang_handeye: model, view_stride, max_views
//                      ceres: init (an instance or type to start from: dlt, zhang), model,
//                             estimate_skew, loss, loss_scale_px, max_iterations, autodiff,
//                             views (frames: every frame, rig constraint; init: the init's own
//                             per-view problem, e.g. zhang's views)
//     reference: {source, method, fku_px, fkv_px, phi_deg, u0_px, v0_px, x_C, theta_err_below}
//     report: {role: noise | points | gain | dynamic}   # the report's question these rows answer
//
// `base:` loads another scenario file first; this file's fields then override it (a `points`,
// `motion` or `reference` section replaces the base's as a whole; a `methods:` list replaces the
// instances, a map updates them). A sweep axis `methods.NAME.field` changes one instance. Unknown
// keys, wrong types and invalid values are errors of the form "FILE:LINE:COL: FIELD: REASON".
#pragma once

#include <string>
#include <vector>

#include "bench/config/scenario.h"

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
