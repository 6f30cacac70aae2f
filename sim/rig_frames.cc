#include "sim/rig_frames.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace calibench {

bool RigFramesOptions::Check(std::string* why) const {
  std::string msg;
  if (rows < 2 || cols < 2) {
    msg = "rows and cols must be >= 2";
  } else if (!(spacing_m > 0)) {
    msg = "spacing_m must be > 0";
  } else if (num_frames < 1) {
    msg = "num_frames must be >= 1";
  } else if (!(max_off_axis_deg >= 0 && max_off_axis_deg < 180)) {
    msg = "max_off_axis_deg must be in [0, 180)";
  } else if (!(range.max_tilt_deg >= 0 && range.max_tilt_deg < 90)) {
    msg = "range.max_tilt_deg must be in [0, 90)";
  } else if (!(range.near_m > 0 && range.far_m >= range.near_m)) {
    msg = "range must have 0 < near_m <= far_m";
  } else if (!(min_visible_fraction > 0 && min_visible_fraction <= 1)) {
    msg = "min_visible_fraction must be in (0, 1]";
  } else if (min_cameras < 1) {
    msg = "min_cameras must be >= 1";
  } else if (!(pixel_sigma_px >= 0)) {
    msg = "pixel_sigma_px must be >= 0";
  } else if (!(edge_margin_px >= 0)) {
    msg = "edge_margin_px must be >= 0";
  } else if (max_attempts < 0) {
    msg = "max_attempts must be >= 0 (0: 50 * num_frames)";
  } else if (std::any_of(anchor_cameras.begin(), anchor_cameras.end(),
                         [](int c) { return c < 0; })) {
    msg = "anchor_cameras must hold camera indices >= 0";
  }
  if (msg.empty()) return true;
  if (why != nullptr) *why = msg;
  return false;
}

namespace {

// The pixels of `board` camera c images inside its image (edge margin kept), before noise: a point
// counts when it is in front of the board's visible side, in the lens's valid region where the
// image does not fold over, and inside [margin, size - 1 - margin] (pixel centres at integers).
View VisibleView(const RigCamera& camera, const Rigid3& cam_from_board,
                 const std::vector<Eigen::Vector3d>& board, double margin_px) {
  View view;
  // The board's front is its +z side (FacingBoardPose): a camera behind it sees nothing.
  if (!(cam_from_board.Inverse().translation.z() > 0)) return view;
  for (const Eigen::Vector3d& p : board) {
    const Eigen::Vector3d point_in_cam = cam_from_board * p;
    Eigen::Vector2d pixel;
    if (!ProjectPoint(camera.intrinsics, point_in_cam, &pixel) ||
        !camera.intrinsics.DistortionIsMonotoneAlong(point_in_cam)) {
      continue;
    }
    if (pixel.x() < margin_px || pixel.y() < margin_px ||
        pixel.x() > camera.image_width - 1 - margin_px ||
        pixel.y() > camera.image_height - 1 - margin_px) {
      continue;
    }
    view.points.push_back(p);
    view.pixels.push_back(pixel);
  }
  return view;
}

}  // namespace

// Per attempt, the draws are: the anchor (uniform index into the anchor list), the off-axis angle,
// then RandomFacingBoardPose's (azimuth, tilt, tilt axis, turn, distance), then the noise of every
// kept pixel (u, v), cameras in order. A rejected attempt has drawn no noise.
SyntheticRigFrames MakeRigFrames(const CameraRig& rig, const RigFramesOptions& options, Rng* rng) {
  SyntheticRigFrames out;
  const int num_cameras = rig.NumCameras();
  std::vector<int> anchors = options.anchor_cameras;
  if (anchors.empty()) {
    for (int c = 0; c < num_cameras; ++c) anchors.push_back(c);
  }
  anchors.erase(std::remove_if(anchors.begin(), anchors.end(),
                               [&](int c) { return c < 0 || c >= num_cameras; }),
                anchors.end());
  if (anchors.empty()) return out;
  const std::vector<Eigen::Vector3d> board =
      BoardPoints(options.rows, options.cols, options.spacing_m);
  const Eigen::Vector3d centre((options.cols - 1) * options.spacing_m / 2,
                               (options.rows - 1) * options.spacing_m / 2, 0);
  const size_t min_points =
      std::max<size_t>(8, static_cast<size_t>(std::ceil(options.min_visible_fraction *
                                                        static_cast<double>(board.size()))));
  const int max_attempts =
      options.max_attempts > 0 ? options.max_attempts : 50 * options.num_frames;
  for (int attempt = 0;
       attempt < max_attempts && static_cast<int>(out.frames.size()) < options.num_frames;
       ++attempt) {
    const int pick =
        std::min(static_cast<int>(rng->Uniform() * static_cast<double>(anchors.size())),
                 static_cast<int>(anchors.size()) - 1);
    const int anchor = anchors[pick];
    const double off_axis_deg = rng->Uniform(0, options.max_off_axis_deg);
    const Rigid3 anchor_from_board =
        RandomFacingBoardPose(centre, off_axis_deg, options.range, rng);
    const Rigid3 rig_from_board = rig.cameras[anchor].cam_from_rig.Inverse() * anchor_from_board;
    RigFrame frame;
    frame.views_by_camera.resize(num_cameras);
    int seen = 0;
    for (int c = 0; c < num_cameras; ++c) {
      View view = VisibleView(rig.cameras[c], rig.cameras[c].cam_from_rig * rig_from_board, board,
                              options.edge_margin_px);
      const bool keep = options.whole_board ? view.points.size() == board.size()
                                            : view.points.size() >= min_points;
      if (!keep) continue;
      frame.views_by_camera[c] = std::move(view);
      ++seen;
    }
    if (seen < options.min_cameras) continue;
    for (View& view : frame.views_by_camera) {
      for (Eigen::Vector2d& pixel : view.pixels) {
        pixel += options.pixel_sigma_px * NormalPair<Eigen::Vector2d>(rng);
      }
    }
    frame.name = std::to_string(out.frames.size());
    out.frames.push_back(std::move(frame));
    out.rig_from_board.push_back(rig_from_board);
    out.anchor.push_back(anchor);
  }
  return out;
}

}  // namespace calibench
