#include "batch/extrinsic_from_views.h"

#include <Eigen/Eigenvalues>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace calibench {

Rigid3 AveragePoses(const std::vector<Rigid3>& poses) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  for (const Rigid3& p : poses) {
    sum += p.rotation;
    position += p.translation;
  }
  return {ProjectToSO3(sum), position / static_cast<double>(poses.size())};
}

bool HandEyeTsai(const std::vector<Rigid3>& parent_from_points,
                 const std::vector<Rigid3>& cam_from_target, Rigid3* parent_from_cam,
                 std::string* why) {
  std::vector<cv::Mat> r_g2b, t_g2b, r_t2c, t_t2c;
  // Tsai's method needs relative rotations about at least two non-parallel axes.
  Eigen::Matrix3d axes = Eigen::Matrix3d::Zero();
  for (size_t i = 1; i < parent_from_points.size(); ++i) {
    const Eigen::AngleAxisd rel(parent_from_points[i].rotation *
                                parent_from_points[i - 1].rotation.transpose());
    if (rel.angle() > 1e-3) axes += rel.axis() * rel.axis().transpose();
  }
  const Eigen::Vector3d spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(axes).eigenvalues();
  if (!(spread[1] > 1e-3 * spread[2])) {
    if (why) {
      *why =
          "hand-eye is degenerate: the body rotates about a single axis (or not at all); "
          "it needs rotations about two non-parallel axes";
    }
    return false;
  }
  for (size_t i = 0; i < cam_from_target.size(); ++i) {
    // Moving: parent_from_points = body_from_world, whose inverse is gripper2base (eye-in-hand).
    // Fixed: parent_from_points = world_from_body, whose inverse is base2gripper (eye-to-hand).
    const Rigid3 gripper = parent_from_points[i].Inverse();
    cv::Mat r, t, rc, tc;
    cv::eigen2cv(Eigen::Matrix3d(gripper.rotation), r);
    cv::eigen2cv(Eigen::Vector3d(gripper.translation), t);
    cv::eigen2cv(Eigen::Matrix3d(cam_from_target[i].rotation), rc);
    cv::eigen2cv(Eigen::Vector3d(cam_from_target[i].translation), tc);
    r_g2b.push_back(r);
    t_g2b.push_back(t);
    r_t2c.push_back(rc);
    t_t2c.push_back(tc);
  }
  if (r_g2b.size() < 3) {
    if (why) *why = "hand-eye needs at least 3 views of board 0";
    return false;
  }
  cv::Mat r_out, t_out;
  try {
    cv::calibrateHandEye(r_g2b, t_g2b, r_t2c, t_t2c, r_out, t_out, cv::CALIB_HAND_EYE_TSAI);
  } catch (const cv::Exception& e) {
    if (why) *why = std::string("cv::calibrateHandEye: ") + e.what();
    return false;
  }
  Eigen::Matrix3d r;
  Eigen::Vector3d t;
  cv::cv2eigen(r_out, r);
  cv::cv2eigen(t_out, t);
  *parent_from_cam = {ProjectToSO3(r), t};
  return parent_from_cam->rotation.allFinite() && t.allFinite();
}

}  // namespace calibench
