#include "metrics/metric_table.h"

#include <stdexcept>

namespace calibench {
namespace {

constexpr unsigned kParameter = kValueColumn | kErrorColumn;            // Estimate and error.
constexpr unsigned kIntrinsic = kParameter | kStdColumn | kCrlbColumn;  // With companions.
constexpr double kAngleTargetDeg = 0.1;  // Pitch and roll to 0.1 deg: Algers 2018, Umeå, §1.2.

// One entry of the table, built by naming what differs from the defaults.
class Entry {
 public:
  Entry(Metric id, const char* name, const char* unit, const char* label, const char* doc) {
    spec_.id = id;
    spec_.name = name;
    spec_.unit = unit;
    spec_.label = label;
    spec_.doc = doc;
  }
  Entry& Columns(unsigned columns) { return spec_.columns = columns, *this; }
  Entry& Integer() { return spec_.integer = true, *this; }
  Entry& Track(int index) { return spec_.track = index, *this; }
  Entry& Summarised(Summary how) { return spec_.summary = how, *this; }
  Entry& Ranked() { return spec_.ranked = true, *this; }
  Entry& Target(double bound) { return spec_.target = bound, *this; }
  Entry& Headline() { return spec_.headline = true, *this; }
  Entry& Projection(const char* role) { return spec_.projection = role, *this; }
  operator MetricSpec() const { return spec_; }  // NOLINT: the table is a list of entries.

 private:
  MetricSpec spec_{};
};

std::vector<MetricSpec> MakeTable() {
  using M = Metric;
  using S = Summary;
  std::vector<MetricSpec> table = {
      Entry(M::kFku, "fku_px", "px", "f·ku", "focal length times the u pixel density")
          .Columns(kIntrinsic)
          .Track(3)
          .Summarised(S::kWithRmse)
          .Ranked()
          .Headline(),
      Entry(M::kFkv, "fkv_px", "px", "f·kv", "focal length times the v pixel density")
          .Columns(kIntrinsic)
          .Track(4)
          .Summarised(S::kWithRmse)
          .Ranked(),
      Entry(M::kU0, "u0_px", "px", "u0", "principal point, u")
          .Columns(kIntrinsic)
          .Track(5)
          .Summarised(S::kWithRmse)
          .Ranked(),
      Entry(M::kV0, "v0_px", "px", "v0", "principal point, v")
          .Columns(kIntrinsic)
          .Track(6)
          .Summarised(S::kWithRmse)
          .Ranked(),
      Entry(M::kPhi, "phi_deg", "deg", "φ", "angle between the image axes (90: no skew)")
          .Columns(kIntrinsic)
          .Summarised(S::kWithRmse)
          .Ranked(),
      Entry(M::kRoll, "roll_deg", "deg", "roll",
            "roll of R_C (yaw-pitch-roll about z, y, x; errors wrapped to (-180, 180])")
          .Columns(kParameter)
          .Track(0)
          .Summarised(S::kWithRmse)
          .Ranked()
          .Target(kAngleTargetDeg),
      Entry(M::kPitch, "pitch_deg", "deg", "pitch", "pitch of R_C (errors wrapped to (-180, 180])")
          .Columns(kParameter)
          .Track(1)
          .Summarised(S::kWithRmse)
          .Ranked()
          .Target(kAngleTargetDeg),
      Entry(M::kYaw, "yaw_deg", "deg", "yaw", "yaw of R_C (errors wrapped to (-180, 180])")
          .Columns(kParameter)
          .Track(2)
          .Summarised(S::kWithRmse)
          .Ranked(),
      // Statistics without an RMSE, as summary.csv has always written them.
      Entry(M::kRotErr, "rot_err_deg", "deg", "geodesic rotation error",
            "angle of R_C estimate R_C^T, the estimate projected onto SO(3)")
          .Summarised(S::kStatistics)
          .Ranked()
          .Headline(),
      Entry(M::kXcX, "xc_x_m", "m", "x_C x", "camera position x_C in the parent frame, x"),
      Entry(M::kXcY, "xc_y_m", "m", "x_C y", "camera position x_C in the parent frame, y"),
      Entry(M::kXcZ, "xc_z_m", "m", "x_C z", "camera position x_C in the parent frame, z"),
      Entry(M::kXcErr, "xc_err_m", "m", "‖x_C error‖", "|x_C estimate - x_C|")
          .Summarised(S::kWithRmse)
          .Ranked(),
      Entry(M::kRmsReproj, "rms_reproj_px", "px", "reprojection RMS",
            "per-point Euclidean RMS of the estimate's projections against the measured pixels "
            "(a fit, not an error against the truth)")
          .Summarised(S::kStatistics)
          .Ranked(),
      Entry(M::kThetaErr, "theta_err_norm", "", "‖θ̃‖",
            "the thesis's error figure ||theta - theta_hat / lambda|| (metrics/metrics.h)")
          .Summarised(S::kStatistics),
      Entry(M::kConvergeTime, "converge_time_s", "s", "convergence time",
            "first time after which ||theta~|| stays below the instance's convergence_tol (NaN: "
            "never)")
          .Summarised(S::kStatistics),
      Entry(M::kOrthoDefect, "ortho_defect", "", "orthogonality defect",
            "||R^T R - I||_F of the recovered rotation before its projection onto SO(3)"),
      Entry(M::kImproper, "improper", "", "improper",
            "1 when the recovered rotation is a reflection")
          .Integer(),
      Entry(M::kSteps, "steps", "", "steps", "integrator steps or solver iterations").Integer(),
      Entry(M::kFramesUsed, "n_frames_used", "", "frames used",
            "frames with an observation that the estimate used (-1: not recorded)")
          .Integer(),
      Entry(M::kObsUsed, "n_obs_used", "", "observations used",
            "corner observations that the estimate used (-1: not recorded)")
          .Integer(),
      Entry(M::kDetectRate, "detect_rate", "", "detection rate",
            "tags detected / tags fully in the image (rendered detections; NaN for oracle)"),
      Entry(M::kCornerRms, "corner_rms_px", "px", "corner RMS",
            "Euclidean RMS of the detected corners against their exact projections (rendered)")
          .Summarised(S::kStatistics),
      Entry(M::kCornerRadialBias, "corner_radial_bias_px", "px", "corner radial bias",
            "mean corner error along the tags' diagonals, > 0 outward (rendered)")
          .Summarised(S::kStatistics),
      Entry(M::kCornerCrlb, "corner_crlb_px", "px", "corner CRLB",
            "RMS of the corners' Cramer-Rao std per axis (rendered, photometric fit)")
          .Summarised(S::kStatistics),
      Entry(M::kFramesNoDetection, "frames_no_detection", "", "frames without detections",
            "frames without any detection (rendered; -1 for oracle)")
          .Integer(),
      // RMSE over trials: the RMS of the per-trial RMS over the image.
      Entry(M::kProjErr, "proj_err_px", "px", "projection error",
            "RMS over a 16-column grid of the truth's image of the distance between a pixel and "
            "where the estimate projects the ray the truth sees there (rays at infinity; pixels "
            "where the truth unprojects; metrics/metrics.h)")
          .Summarised(S::kWithRmse)
          .Projection("error"),
      // RMSE over trials: the RMS of the ratio, ~1 for a method that knows its uncertainty.
      Entry(M::kProjErrRatio, "proj_err_ratio", "", "projection error / predicted std",
            "proj_err_px over the RMS on the same grid of the projection error the estimate's "
            "covariance predicts (sqrt of the trace of each pixel's covariance): ~1 consistent, "
            ">> 1 overconfident (NaN: no covariance (adaptive, zhang, dlt), or a lens model with "
            "free distortion terms, which the covariance lacks)")
          .Summarised(S::kWithRmse)
          .Projection("ratio"),
  };
  for (size_t i = 0; i < table.size(); ++i) {  // A programmer error: the table is out of order.
    if (static_cast<size_t>(table[i].id) != i) {
      throw std::logic_error(std::string("metric table: ") + table[i].name + " out of order");
    }
  }
  return table;
}

}  // namespace

const std::vector<MetricSpec>& MetricTable() {
  static const std::vector<MetricSpec> table = MakeTable();
  return table;
}

const MetricSpec& Spec(Metric metric) { return MetricTable().at(static_cast<size_t>(metric)); }

std::string ColumnName(Metric metric, MetricColumn column) {
  return ColumnName(Spec(metric), column);
}

std::string ColumnName(const MetricSpec& spec, MetricColumn column) {
  if (!(spec.columns & column)) {
    throw std::logic_error(std::string("metric table: ") + spec.name + " has no such column");
  }
  switch (column) {
    case kValueColumn:
      return spec.name;
    case kErrorColumn:
      return std::string("err_") + spec.name;
    case kStdColumn:
      return std::string("std_") + spec.name;
    case kCrlbColumn:
      return std::string("crlb_") + spec.name;
  }
  return spec.name;
}

std::string SummaryColumn(const MetricSpec& spec) {
  return ColumnName(spec, spec.columns & kErrorColumn ? kErrorColumn : kValueColumn);
}

std::string ColumnDoc(const MetricSpec& spec, MetricColumn column) {
  const std::string label = spec.label;
  switch (column) {
    case kValueColumn:
      return spec.columns & kErrorColumn ? label + " estimated: " + spec.doc : spec.doc;
    case kErrorColumn:
      return label + ", estimate minus truth";
    case kStdColumn:
      return label + ", the standard deviation the method reports (NaN: none)";
    case kCrlbColumn:
      return label +
             ", the Cramer-Rao standard deviation of the method's parametrisation (white pixel "
             "noise only)";
  }
  return spec.doc;
}

}  // namespace calibench
