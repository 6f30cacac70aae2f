// InitRigExtrinsics (batch/rig_refine.h): pairwise relative poses, their robust average, the
// maximum spanning tree over the cameras and the chaining along it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>

#include "batch/rig_refine.h"

namespace calibench {
namespace {

// The robust average of pose measurements (InitRigExtrinsics' header comment): the geodesic
// median of the rotations (the measurement with the least sum of angles to the others: a medoid,
// exact and robust for the handful of measurements a pair has), those within kInitOutlierDeg of
// it averaged by the chordal L2 mean (the projection of their sum onto SO(3)), the translations by
// their per-axis median over the same inliers. *outliers gets the indices dropped.
Rigid3 RobustAverage(const std::vector<Rigid3>& poses, std::vector<int>* outliers) {
  const size_t n = poses.size();
  size_t median = 0;
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < n; ++i) {
    double sum = 0;
    for (size_t j = 0; j < n; ++j) {
      if (j != i) sum += RotationAngleDeg(poses[i].rotation, poses[j].rotation);
    }
    if (sum < best) best = sum, median = i;
  }
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  std::vector<double> x, y, z;
  for (size_t i = 0; i < n; ++i) {
    if (RotationAngleDeg(poses[i].rotation, poses[median].rotation) > kInitOutlierDeg) {
      if (outliers != nullptr) outliers->push_back(static_cast<int>(i));
      continue;
    }
    sum += poses[i].rotation;
    x.push_back(poses[i].translation.x());
    y.push_back(poses[i].translation.y());
    z.push_back(poses[i].translation.z());
  }
  const auto median_of = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return v.size() % 2 == 1 ? v[m] : 0.5 * (v[m - 1] + v[m]);
  };
  return {ProjectToSO3(sum), Eigen::Vector3d(median_of(x), median_of(y), median_of(z))};
}

// The board points two views share (equal board coordinates: the same target).
int SharedCorners(const View& a, const View& b) {
  std::map<std::tuple<double, double, double>, int> in_a;
  for (const Eigen::Vector3d& p : a.points) in_a[{p.x(), p.y(), p.z()}] = 1;
  int shared = 0;
  for (const Eigen::Vector3d& p : b.points) shared += in_a.count({p.x(), p.y(), p.z()}) ? 1 : 0;
  return shared;
}

std::string CameraName(const CameraRig& rig, int c) {
  return rig.cameras[c].name.empty() ? "camera " + std::to_string(c) : rig.cameras[c].name;
}

}  // namespace

RigInitSummary InitRigExtrinsics(const std::vector<RigFrame>& frames,
                                 const std::vector<std::vector<Rigid3>>& cam_from_board,
                                 const std::vector<std::vector<bool>>& has_pose, CameraRig* rig,
                                 std::vector<Rigid3>* rig_from_board) {
  const SummaryClock clock;
  RigInitSummary summary;
  const auto fail = [&](const std::string& message) {
    return clock.Finish(&summary, MethodStatus::kFailed, message);
  };
  const int num_cameras = rig->NumCameras();
  const int num_frames = static_cast<int>(frames.size());
  if (num_cameras < 2) return fail("rig init: a rig needs at least 2 cameras");
  if (static_cast<int>(cam_from_board.size()) != num_cameras ||
      static_cast<int>(has_pose.size()) != num_cameras) {
    return fail("rig init: cam_from_board and has_pose need one entry per camera");
  }
  for (int c = 0; c < num_cameras; ++c) {
    if (static_cast<int>(cam_from_board[c].size()) != num_frames ||
        static_cast<int>(has_pose[c].size()) != num_frames) {
      return fail("rig init: " + CameraName(*rig, c) + ": need one board pose slot per frame");
    }
  }
  for (int f = 0; f < num_frames; ++f) {
    if (static_cast<int>(frames[f].views_by_camera.size()) != num_cameras) {
      return fail("rig init: frame " + std::to_string(f) + " does not hold one view per camera");
    }
  }
  const auto seen = [&](int c, int f) {
    return has_pose[c][f] && !frames[f].views_by_camera[c].points.empty();
  };

  // Edge weights: the corners both cameras of a pair saw in the frames both have a pose for.
  std::vector<std::vector<int>> weight(num_cameras, std::vector<int>(num_cameras, 0));
  for (int f = 0; f < num_frames; ++f) {
    for (int a = 0; a < num_cameras; ++a) {
      for (int b = a + 1; b < num_cameras; ++b) {
        if (!seen(a, f) || !seen(b, f)) continue;
        const int shared =
            SharedCorners(frames[f].views_by_camera[a], frames[f].views_by_camera[b]);
        weight[a][b] += shared;
        weight[b][a] += shared;
      }
    }
  }

  // Prim's maximum spanning tree from camera 0 (ties: the lower camera index).
  summary.parent.assign(num_cameras, -1);
  summary.shared_points.assign(num_cameras, 0);
  summary.outlier_frames.assign(num_cameras, {});
  std::vector<bool> in_tree(num_cameras, false);
  std::vector<int> order = {0};  // Cameras in the order they join: parents before children.
  in_tree[0] = true;
  for (;;) {
    int best_child = -1, best_parent = -1, best_weight = 0;
    for (int p : order) {
      for (int c = 0; c < num_cameras; ++c) {
        if (in_tree[c] || weight[p][c] <= best_weight) continue;
        best_weight = weight[p][c], best_child = c, best_parent = p;
      }
    }
    if (best_child < 0) break;
    in_tree[best_child] = true;
    summary.parent[best_child] = best_parent;
    summary.shared_points[best_child] = best_weight;
    order.push_back(best_child);
  }
  if (static_cast<int>(order.size()) < num_cameras) {
    std::string cut;
    for (int c = 0; c < num_cameras; ++c) {
      if (!in_tree[c]) cut += (cut.empty() ? "" : ", ") + CameraName(*rig, c);
    }
    return fail("rig init: no frame links " + cut + " to " + CameraName(*rig, 0) +
                " (directly or through other cameras): cut off from the rig");
  }

  // Each tree edge's relative pose, chained from camera 0.
  rig->cameras[0].cam_from_rig = Rigid3();
  for (size_t k = 1; k < order.size(); ++k) {
    const int child = order[k], parent = summary.parent[child];
    std::vector<Rigid3> measured;
    std::vector<int> measured_frame;
    for (int f = 0; f < num_frames; ++f) {
      if (!seen(child, f) || !seen(parent, f)) continue;
      measured.push_back(cam_from_board[child][f] * cam_from_board[parent][f].Inverse());
      measured_frame.push_back(f);
    }
    std::vector<int> outliers;
    const Rigid3 child_from_parent = RobustAverage(measured, &outliers);
    for (int i : outliers) summary.outlier_frames[child].push_back(measured_frame[i]);
    if (2 * outliers.size() > measured.size()) {
      return fail("rig init: the frames of " + CameraName(*rig, child) + " and " +
                  CameraName(*rig, parent) + " disagree: no majority within " +
                  std::to_string(kInitOutlierDeg) + " deg of their median relative rotation");
    }
    rig->cameras[child].cam_from_rig = child_from_parent * rig->cameras[parent].cam_from_rig;
  }

  // Each frame's pose in the rig: the robust average over the cameras that saw it.
  rig_from_board->assign(num_frames, Rigid3());
  for (int f = 0; f < num_frames; ++f) {
    std::vector<Rigid3> measured;
    for (int c = 0; c < num_cameras; ++c) {
      if (seen(c, f)) {
        measured.push_back(rig->cameras[c].cam_from_rig.Inverse() * cam_from_board[c][f]);
      }
    }
    if (!measured.empty()) (*rig_from_board)[f] = RobustAverage(measured, nullptr);
  }
  std::ostringstream note;
  note << "tree:";
  for (int c = 1; c < num_cameras; ++c) {
    note << " " << summary.parent[c] << "->" << c << " (" << summary.shared_points[c]
         << " corners)";
  }
  return clock.Finish(&summary, MethodStatus::kOk, note.str());
}

}  // namespace calibench
