// rig.csv (bench/run/run_row.h: RigColumns, RigLines): one line per (scenario, trial, method,
// camera c >= 1), the relative pose of camera c against camera 0 (RigRow).
#include <functional>
#include <string>
#include <vector>

#include "bench/run/csv.h"
#include "bench/run/run_row.h"
#include "util/format.h"

namespace calibench {

namespace {

// rig.csv's columns: how to write each from a row (its RigRow set).
struct RigColumn {
  ColumnInfo info;
  std::function<std::string(const RunRow&, const RigRow&)> get;
};

RigColumn RigNumber(const char* name, const char* unit, const char* doc,
                    const std::function<double(const RigRow&)>& value) {
  return {{name, unit, doc},
          [value](const RunRow&, const RigRow& g) { return FormatNumber(value(g)); }};
}

const std::vector<RigColumn>& RigLayout() {
  static const std::vector<RigColumn> columns = {
      {{"scenario", "", "scenario name"},
       [](const RunRow& r, const RigRow&) { return r.scenario; }},
      {{"sweep", "", "the swept scenario's name"},
       [](const RunRow& r, const RigRow&) { return r.sweep; }},
      {{"point", "", "sweep point"},
       [](const RunRow& r, const RigRow&) { return std::to_string(r.point); }},
      {{"params", "", "the sweep point's field=value;..."},
       [](const RunRow& r, const RigRow&) { return r.params; }},
      {{"trial", "", "Monte Carlo trial"},
       [](const RunRow& r, const RigRow&) { return std::to_string(r.trial); }},
      {{"seed", "", "the trial's seed"},
       [](const RunRow& r, const RigRow&) { return std::to_string(r.seed); }},
      {{"method", "", "the method instance (the same on both cameras)"},
       [](const RunRow& r, const RigRow&) { return r.method; }},
      {{"camera", "", "camera c >= 1 of the pair (camera 0, c): its index in rig.cameras"},
       [](const RunRow& r, const RigRow&) { return std::to_string(r.camera); }},
      {{"status", "", "ok when both cameras' rows are ok; else the first other status"},
       [](const RunRow&, const RigRow& g) { return g.status; }},
      RigNumber("err_rel_rx_deg", "deg",
                "relative rotation error Log(R_est R_true^T) of cam_c_from_cam_0, about camera "
                "c's x axis (pitch), at the end of the run",
                [](const RigRow& g) { return g.errors.rel_rot_err_deg[0]; }),
      RigNumber("err_rel_ry_deg", "deg", "the same about camera c's y axis (yaw)",
                [](const RigRow& g) { return g.errors.rel_rot_err_deg[1]; }),
      RigNumber("err_rel_rz_deg", "deg", "the same about camera c's z axis (roll)",
                [](const RigRow& g) { return g.errors.rel_rot_err_deg[2]; }),
      RigNumber("rel_rot_err_deg", "deg", "the relative rotation's geodesic error (the norm)",
                [](const RigRow& g) { return g.errors.rel_rot_err_norm_deg; }),
      RigNumber("err_baseline_mm", "mm", "|t_est| - |t_true| of cam_c_from_cam_0",
                [](const RigRow& g) { return g.errors.baseline_err_mm; }),
      RigNumber("vdisp_rms_px", "px",
                "RMS vertical disparity of the true projections of a 5 x 5 grid on a plane 10 m "
                "ahead, rectified with the estimated rig (f: camera 0's f*kv)",
                [](const RigRow& g) { return g.errors.vdisp_rms_px; }),
      RigNumber("vdisp_max_px", "px", "the largest |vertical disparity| of that grid",
                [](const RigRow& g) { return g.errors.vdisp_max_px; }),
      RigNumber("depth_err_10m_pct", "pct",
                "depth from the disparity through the estimated rig of a point 10 m ahead on "
                "camera 0's axis, minus the true depth, in percent of it",
                [](const RigRow& g) { return g.errors.depth_err_near_pct; }),
      RigNumber("depth_err_30m_pct", "pct", "the same at 30 m",
                [](const RigRow& g) { return g.errors.depth_err_far_pct; }),
      RigNumber("segment_from_s", "s",
                "tracking: the start of the segment the figures below cover (the last truth "
                "change moving camera 0 or c; 0 when none); NaN: not a tracking scenario",
                [](const RigRow& g) { return g.segment_from_s; }),
      RigNumber(
          "rel_rot_tol_deg", "deg",
          "tracking: the tolerance of the re-convergence (the largest of tracking.tolerance's "
          "roll, pitch and yaw)",
          [](const RigRow& g) { return g.rel_rot_tol_deg; }),
      RigNumber("rel_rot_reconverge_s", "s",
                "tracking: first time after the segment's start from which rel_rot_err_deg stays "
                "within the tolerance to the end (NaN: never)",
                [](const RigRow& g) { return g.rel_rot.reconverge_s; }),
      RigNumber("rel_rot_steady_err_deg", "deg",
                "tracking: median rel_rot_err_deg over the last steady_fraction of the segment",
                [](const RigRow& g) { return g.rel_rot.steady_err; }),
      RigNumber("rel_rot_peak_err_deg", "deg", "tracking: max rel_rot_err_deg over the segment",
                [](const RigRow& g) { return g.rel_rot.peak_err; }),
      RigNumber("baseline_steady_err_mm", "mm",
                "tracking: median |err_baseline_mm| over the last steady_fraction of the segment",
                [](const RigRow& g) { return g.baseline_mm.steady_err; }),
      RigNumber("vdisp_steady_rms_px", "px",
                "tracking: median vdisp_rms_px over the last steady_fraction of the segment",
                [](const RigRow& g) { return g.vdisp_rms_px.steady_err; }),
  };
  return columns;
}

}  // namespace

const std::vector<ColumnInfo>& RigColumns() {
  static const std::vector<ColumnInfo> columns = [] {
    std::vector<ColumnInfo> out;
    for (const RigColumn& c : RigLayout()) out.push_back(c.info);
    return out;
  }();
  return columns;
}

std::string RigLines(const RunRow& r) {
  if (!r.rig) return "";
  std::vector<std::string> fields;
  for (const RigColumn& c : RigLayout()) fields.push_back(c.get(r, *r.rig));
  return CsvLine(fields);
}

}  // namespace calibench
