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

void EmitAprilGrid(YAML::Emitter& out, const AprilGrid& g, const Eigen::Vector3d& rpy_deg) {
  out << YAML::Flow << YAML::BeginMap << YAML::Key << "family" << YAML::Value << g.family
      << YAML::Key << "tag_rows" << YAML::Value << g.tag_rows << YAML::Key << "tag_cols"
      << YAML::Value << g.tag_cols << YAML::Key << "tag_size_m" << YAML::Value << g.tag_size_m
      << YAML::Key << "tag_spacing" << YAML::Value << g.tag_spacing << YAML::Key << "first_id"
      << YAML::Value << g.first_id << YAML::Key << "black_tag_border" << YAML::Value
      << g.black_tag_border << YAML::Key << "corner_squares" << YAML::Value << g.corner_squares
      << YAML::Key << "origin" << YAML::Value;
  EmitVector(out, g.points_from_board.translation);
  out << YAML::Key << "rpy_deg" << YAML::Value;
  EmitVector(out, rpy_deg);
  out << YAML::EndMap;
}

void EmitRendering(YAML::Emitter& out, const RenderedSourceOptions& o) {
  const RenderOptions& ro = o.render;
  const AprilTagOptions& a = o.detection.detector;
  out << YAML::BeginMap << YAML::Key << "supersample" << YAML::Value << ro.supersample << YAML::Key
      << "blur_sigma_px" << YAML::Value << ro.blur_sigma_px << YAML::Key << "blur_grid"
      << YAML::Value << ro.blur_grid << YAML::Key << "noise_sigma_gray" << YAML::Value
      << ro.noise_sigma_gray << YAML::Key << "background_gray" << YAML::Value << ro.background_gray
      << YAML::Key << "black_gray" << YAML::Value << ro.black_gray << YAML::Key << "white_gray"
      << YAML::Value << ro.white_gray << YAML::Key << "threads" << YAML::Value << o.threads
      << YAML::Key << "corner_refinement" << YAML::Value
      << CornerRefinementName(o.detection.refinement) << YAML::Key << "min_border_distance_px"
      << YAML::Value << o.detection.min_border_distance_px << YAML::Key << "corner_error_clip_px"
      << YAML::Value << o.corner_error_clip_px << YAML::Key << "corner_error_part" << YAML::Value
      << CornerErrorPartName(o.corner_error_part) << YAML::Key << "corner_error_grid" << YAML::Value
      << o.corner_error_grid << YAML::Key << "detector" << YAML::Value << YAML::Flow
      << YAML::BeginMap << YAML::Key << "quad_decimate" << YAML::Value << a.quad_decimate
      << YAML::Key << "quad_sigma" << YAML::Value << a.quad_sigma << YAML::Key << "refine_edges"
      << YAML::Value << a.refine_edges << YAML::Key << "decode_sharpening" << YAML::Value
      << a.decode_sharpening << YAML::Key << "threads" << YAML::Value << a.threads << YAML::Key
      << "max_hamming" << YAML::Value << a.max_hamming << YAML::EndMap << YAML::EndMap;
}

}  // namespace

void config_internal::EmitCamera(YAML::Emitter& out, const CameraSpec& c,
                                 const std::vector<CalibrationChange>* changes) {
  const CameraIntrinsics& k = c.intrinsics;
  out << YAML::BeginMap << YAML::Key << "intrinsics" << YAML::Value << YAML::Flow << YAML::BeginMap
      << YAML::Key << "fku_px" << YAML::Value << k.fku_px << YAML::Key << "fkv_px" << YAML::Value
      << k.fkv_px << YAML::Key << "phi_deg" << YAML::Value << k.phi_deg << YAML::Key << "u0_px"
      << YAML::Value << k.u0_px << YAML::Key << "v0_px" << YAML::Value << k.v0_px << YAML::Key
      << "k1" << YAML::Value << k.k1 << YAML::Key << "k2" << YAML::Value << k.k2 << YAML::Key
      << "p1" << YAML::Value << k.p1 << YAML::Key << "p2" << YAML::Value << k.p2 << YAML::Key
      << "k3" << YAML::Value << k.k3;
  if (k.family != LensFamily::kRadTan) {  // Radtan files stay as they were.
    out << YAML::Key << "k4" << YAML::Value << k.k4 << YAML::Key << "lens_family" << YAML::Value
        << ToString(k.family);
  }
  if (k.family == LensFamily::kUnified || k.family == LensFamily::kDoubleSphere) {
    out << YAML::Key << "xi" << YAML::Value << k.xi;
  }
  if (k.family == LensFamily::kEucm || k.family == LensFamily::kDoubleSphere) {
    out << YAML::Key << "alpha" << YAML::Value << k.alpha;
  }
  if (k.family == LensFamily::kEucm) out << YAML::Key << "beta" << YAML::Value << k.beta;
  out << YAML::EndMap;
  out << YAML::Key << "R_C" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int r = 0; r < 3; ++r) EmitVector(out, c.r_c.row(r).transpose());
  out << YAML::EndSeq << YAML::Key << "x_C" << YAML::Value;
  EmitVector(out, c.x_c);
  out << YAML::Key << "allow_improper_rotation" << YAML::Value << c.allow_improper_rotation;
  if (changes != nullptr && !changes->empty()) {
    out << YAML::Key << "changes" << YAML::Value << YAML::BeginSeq;
    for (const CalibrationChange& e : *changes) {
      const bool step = e.kind == CalibrationChange::Kind::kStep;
      out << YAML::Flow << YAML::BeginMap << YAML::Key << "kind" << YAML::Value
          << (step ? "step" : "ramp");
      if (step) {
        out << YAML::Key << "at_s" << YAML::Value << e.from_s;
      } else {
        out << YAML::Key << "from_s" << YAML::Value << e.from_s << YAML::Key << "to_s"
            << YAML::Value << e.to_s;
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
  out << YAML::EndMap;
}

namespace {

using config_internal::EmitCamera;

void EmitScenario(YAML::Emitter& out, const ScenarioConfig& s) {
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << s.name;
  out << YAML::Key << "description" << YAML::Value << s.description;
  out << YAML::Key << "case" << YAML::Value << ToString(s.calibration_case);
  out << YAML::Key << "duration_s" << YAML::Value << s.duration_s;
  out << YAML::Key << "seed" << YAML::Value << s.seed;
  out << YAML::Key << "paired_sweep" << YAML::Value << s.paired_sweep;
  out << YAML::Key << "trials" << YAML::Value << s.trials;
  out << YAML::Key << "truth" << YAML::Value;
  EmitCamera(out, s.truth, &s.truth_changes);
  out << YAML::Key << "image_size" << YAML::Value << YAML::Flow << YAML::BeginSeq << s.image_width
      << s.image_height << YAML::EndSeq;
  out << YAML::Key << "points" << YAML::Value << YAML::BeginMap;
  if (!s.boards.empty()) {
    out << YAML::Key << "boards" << YAML::Value << YAML::BeginSeq;
    for (size_t i = 0; i < s.boards.size(); ++i) {
      const PlanarBoard& b = s.boards[i];
      out << YAML::Flow << YAML::BeginMap << YAML::Key << "rows" << YAML::Value << b.rows
          << YAML::Key << "cols" << YAML::Value << b.cols << YAML::Key << "spacing_m" << YAML::Value
          << b.spacing_m << YAML::Key << "origin" << YAML::Value;
      EmitVector(out, b.points_from_board.translation);
      out << YAML::Key << "rpy_deg" << YAML::Value;
      EmitVector(out, i < s.board_rpy_deg.size() ? s.board_rpy_deg[i]
                                                 : RollPitchYawDeg(b.points_from_board.rotation));
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  } else if (!s.aprilgrids.empty()) {
    out << YAML::Key << "aprilgrids" << YAML::Value << YAML::BeginSeq;
    for (size_t i = 0; i < s.aprilgrids.size(); ++i) {
      const AprilGrid& g = s.aprilgrids[i];
      EmitAprilGrid(out, g,
                    i < s.aprilgrid_rpy_deg.size() ? s.aprilgrid_rpy_deg[i]
                                                   : RollPitchYawDeg(g.points_from_board.rotation));
    }
    out << YAML::EndSeq;
  } else {
    out << YAML::Key << "list" << YAML::Value << YAML::BeginSeq;
    for (const Eigen::Vector3d& p : s.points) EmitVector(out, p);
    out << YAML::EndSeq;
  }
  out << YAML::EndMap;
  const TwistProfile& m = s.motion;
  out << YAML::Key << "motion" << YAML::Value << YAML::BeginMap;
  const std::pair<const char*, const Eigen::Vector3d*> parts[] = {
      {"v_const", &m.v_const}, {"v_cos", &m.v_cos}, {"v_sin", &m.v_sin},
      {"w_const", &m.w_const}, {"w_cos", &m.w_cos}, {"w_sin", &m.w_sin}};
  for (const auto& [key, v] : parts) {
    out << YAML::Key << key << YAML::Value;
    EmitVector(out, *v);
  }
  out << YAML::Key << "frequency_rad_s" << YAML::Value << m.frequency_rad_s;
  out << YAML::Key << "frame" << YAML::Value
      << (m.frame == TwistProfile::Frame::kWorld ? "world" : "body") << YAML::Key << "random_phase"
      << YAML::Value << s.motion_random_phase << YAML::EndMap;
  out << YAML::Key << "measurements" << YAML::Value << YAML::BeginMap << YAML::Key << "detections"
      << YAML::Value << s.detections << YAML::Key << "sample_rate_hz" << YAML::Value
      << s.measurements.sample_rate_hz << YAML::Key << "eval_rate_hz" << YAML::Value
      << s.measurements.eval_rate_hz << YAML::Key << "outside_image" << YAML::Value
      << s.outside_image << YAML::EndMap;
  const NoiseOptions& n = s.measurements.noise;
  out << YAML::Key << "noise" << YAML::Value << YAML::BeginMap << YAML::Key << "point_sigma_m"
      << YAML::Value << n.point_sigma_m << YAML::Key << "pixel_sigma_px" << YAML::Value
      << n.pixel_sigma_px << YAML::Key << "hold_s" << YAML::Value << n.hold_s << YAML::Key
      << "hold_frames" << YAML::Value << n.hold_frames << YAML::Key << "tag_radial_bias_px"
      << YAML::Value << n.tag_radial_bias_px << YAML::EndMap;
  out << YAML::Key << "rendering" << YAML::Value;
  EmitRendering(out, s.rendering);
  out << YAML::Key << "methods" << YAML::Value;
  config_internal::EmitMethods(out, s);
  const TrackingConfig& t = s.tracking;
  out << YAML::Key << "tracking" << YAML::Value << YAML::BeginMap << YAML::Key << "enabled"
      << YAML::Value << t.enabled << YAML::Key << "report_rate_hz" << YAML::Value
      << t.report_rate_hz << YAML::Key << "band_samples" << YAML::Value << t.band_samples
      << YAML::Key << "steady_fraction" << YAML::Value << t.metrics.steady_fraction << YAML::Key
      << "tolerance" << YAML::Value << YAML::Flow << YAML::BeginMap;
  for (int q = 0; q < kTrackQuantities; ++q) {
    out << YAML::Key << TrackQuantityNames()[q] << YAML::Value << t.metrics.tolerance[q];
  }
  out << YAML::EndMap << YAML::EndMap;
  const Reference& ref = s.reference;
  if (ref.Any() || !ref.source.empty()) {
    out << YAML::Key << "reference" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "source" << YAML::Value << ref.source;
    if (!ref.method.empty()) out << YAML::Key << "method" << YAML::Value << ref.method;
    const std::pair<const char*, double> values[] = {
        {"fku_px", ref.fku_px}, {"fkv_px", ref.fkv_px}, {"phi_deg", ref.phi_deg},
        {"u0_px", ref.u0_px},   {"v0_px", ref.v0_px},   {"theta_err_below", ref.theta_err_below}};
    for (const auto& [key, v] : values) {
      if (std::isfinite(v)) out << YAML::Key << key << YAML::Value << v;
    }
    if (ref.x_c.allFinite()) {
      out << YAML::Key << "x_C" << YAML::Value;
      EmitVector(out, ref.x_c);
    }
    out << YAML::EndMap;
  }
  if (!s.report.role.empty()) {
    out << YAML::Key << "report" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
        << "role" << YAML::Value << s.report.role << YAML::EndMap;
  }
  const SweepPoint& p = s.sweep_point;
  if (p.measurement_index >= 0) {
    out << YAML::Key << "sweep_point" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "sweep" << YAML::Value << p.sweep;
    out << YAML::Key << "index" << YAML::Value << p.index;
    out << YAML::Key << "measurement_index" << YAML::Value << p.measurement_index;
    out << YAML::Key << "params" << YAML::Value << p.params;
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

}  // namespace

std::string ResolvedYaml(const RunConfig& config) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::Comment("calibench resolved configuration: every default filled in");
  out << YAML::BeginMap << YAML::Key << "scenarios" << YAML::Value << YAML::BeginSeq;
  for (const ScenarioConfig& s : config.scenarios) EmitScenario(out, s);
  out << YAML::EndSeq << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace calibench
