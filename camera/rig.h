// A camera rig: N >= 2 cameras fixed to each other, each with its own lens family, intrinsics and
// image size. THE one place that states calibench's rig conventions (the batch solve, the files,
// the bench and the report read them from here).
//
// Frames and poses (camera/pose.h: b_from_a maps a point of A into B):
//   rig frame R      = camera 0's frame. cameras[0].cam_from_rig is the identity (Check).
//   cam_from_rig     camera c's extrinsic: point_in_cam_c = cam_from_rig_c * point_in_rig.
//   cam_i_from_cam_j = cam_from_rig_i * cam_from_rig_j^-1 (CamFromCam(i, j)).
//   rig_from_board   a frame's pose of the target (one per synchronised frame, the batch solve's
//                    nuisance parameters); point_in_cam_c = cam_from_rig_c * rig_from_board * X.
// The relative pose of camera c reported to users is cam_c_from_cam_0 = cam_from_rig_c:
//   relative rotation   its rotation vector r (Rodrigues, degrees), r = Log(R); the components
//                       are the turns about camera c's x, y, z axes (x right, y down, z along the
//                       optical axis: pitch, yaw, roll of the camera for small angles). OpenCV's
//                       stereoCalibrate R (p_cam2 = R p_cam1 + T) is this R for c = 1, mrcal's
//                       rt_cam_ref is (r, t), Kalibr's T_cn_cnm1 is CamFromCam(n, n - 1).
//   baseline            t = translation of cam_from_rig_c: camera 0's centre seen from camera c,
//                       |t| = the distance between the two centres (metres, the target's unit);
//                       camera c's centre in the rig frame is -R^T t (CentreInRig).
// Units: metres for lengths (a target given in squares gives squares), pixels, degrees in names.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/pose.h"
#include "camera/view.h"

namespace calibench {

struct RigCamera {
  std::string name;  // "cam0", or the source the camera came from (a folder, a glob).
  CameraIntrinsics intrinsics;
  LensModel lens_model = LensModel::kPinholeK2;  // The model its intrinsics are estimated with.
  int image_width = 0, image_height = 0;         // 0: unknown (any size fits).
  Rigid3 cam_from_rig;                           // Identity for camera 0.
};

struct CameraRig {
  std::vector<RigCamera> cameras;

  int NumCameras() const { return static_cast<int>(cameras.size()); }
  // cam_i_from_cam_j (header comment).
  Rigid3 CamFromCam(int i, int j) const;
  // Camera c's optical centre in the rig frame (camera 0's), metres.
  Eigen::Vector3d CentreInRig(int c) const;
  // |translation of cam_from_rig_c|: the distance between camera c's and camera 0's centres.
  double BaselineM(int c) const;
  // Log of cam_from_rig_c's rotation (header comment), degrees per axis.
  Eigen::Vector3d RelativeRotationDeg(int c) const;

  // At least two cameras; every intrinsics valid (CameraIntrinsics::Check) and of its lens
  // model's family; image sizes >= 0 and both set or both 0; camera 0's cam_from_rig the
  // identity (to 1e-9); every rotation proper (CheckRotation, 1e-6) and finite; no other camera
  // at camera 0's centre (baseline > 1e-9 m). False with *why naming the camera (its name, else its
  // index) and the field.
  bool Check(std::string* why) const;
};

// One synchronised instant of a rig: views_by_camera[c] is what camera c saw of the target (points
// in the board frame, their pixels; empty: nothing).
struct RigFrame {
  std::vector<View> views_by_camera;
  std::string name;  // For messages (e.g. the image stem "07"); empty: "frame <index>".
};

}  // namespace calibench
