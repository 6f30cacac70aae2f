// Synthetic ground truth as a library (tests and the bench both use it).
//
//  - The thesis's feature points and motion presets (spec "Thesis experiments").
//  - Random valid cameras and extrinsics for property tests, drawn from a seeded Rng.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/pose.h"
#include "camera/view.h"
#include "sim/measurements.h"
#include "sim/motion.h"
#include "sim/render.h"
#include "sim/scene.h"
#include "util/random.h"

namespace calibench {

// The ten feature points of thesis section 2.6 (x_bar at t = 0); the first `count` are used,
// as the thesis drops the right-hand columns. count must be in [1, 10].
std::vector<Eigen::Vector3d> ThesisFeaturePoints(int count);

// Thesis motion presets (spec "Motions"): "none", "small", "large", "rotation",
// "small+rotation". A preset is defined by the moving-camera body twist the thesis prints,
//   small: v_c = [-.05 cos t, -.003, -.15 sin t];  large: v_c = [-.5 cos t, -.13, -.65 sin t];
//   rotation: w_c = [.1, .2, -.1]  (feature points then move as d/dt x = -v_c - w_c x x),
// and resolved per case so that both cases see the same point motion: moving camera -> body
// twist (v_c, w_c); fixed camera -> spatial twist (-v_c, -w_c) (d/dt x = v + w x x; for "small"
// this is the thesis's fixed-camera body velocity v = [.05 cos t, .003, .15 sin t]).
enum class ThesisMotion { kNone, kSmall, kLarge, kRotation, kSmallRotation };
TwistProfile ThesisMotionPreset(ThesisMotion motion, CalibrationCase c);
// Each preset with its name in configs, in declaration order.
const std::vector<std::pair<ThesisMotion, const char*>>& ThesisMotionNames();

// The thesis's cameras 1, 2, 3 (spec "Thesis experiments"). As printed, cameras 2 and 3 have an
// improper R_C (det = -1; allow_improper_rotation is set); proper = true gives the physically
// valid variant (first column negated, same depths). camera must be 1, 2 or 3.
CameraSpec ThesisCamera(int camera, bool proper = false);

// The initial estimate of every thesis simulation (appendix B.1): f*ku 820, f*kv 810, phi 90 deg,
// (u0, v0) = (320, 240), R_C = [[-1, 0, 0], [0, 0, 1], [0, 1, 0]], x_C = (0, -2, 0.5).
CameraSpec ThesisInitialGuess();

// A thesis simulation (section 2.6, sims 1-17) as synthetic ground truth: the scene (T = 240 s,
// continuous measurements), the gain alpha, the measurement noise (variance as printed, each draw
// held 0.1 s) and the seed configs/thesis/simNN.yaml uses (1000 + sim). Sims 2 and 4-17 use the
// printed improper cameras unless `proper`.
struct ThesisSimulation {
  int sim = 0;
  SceneTruth scene;
  double alpha = 1000.0;
  OracleOptions measurements;  // Continuous, eval_rate_hz 10, noise as above.
  uint64_t seed = 0;
};
// nullopt for a sim outside 1..17.
std::optional<ThesisSimulation> MakeThesisSimulation(int sim, bool proper = false);

// configs/batch/rig_moving.yaml's scene as ground truth: a moving camera (thesis camera 1 without
// skew) before two 8 x 11 planar boards (8 cm pitch) 40 degrees apart, fixed in the world, the
// body swaying about a wandering axis (rotations about two axes: hand-eye is determined) for 60 s.
struct BoardRigScene {
  SceneTruth scene;
  std::vector<PlanarBoard> boards;
  std::vector<BoardLayout> layouts;  // As the batch methods see them (sim/target.h).
};
BoardRigScene SwayingBoardRig();

struct RandomCameraOptions {
  double min_focal_px = 200.0, max_focal_px = 2000.0;
  double min_phi_deg = 60.0, max_phi_deg = 120.0;
  double max_principal_offset_px = 400.0;  // |u0|, |v0| drawn in [0, this].
  double max_translation_m = 10.0;
};

CameraIntrinsics RandomIntrinsics(const RandomCameraOptions& options, Rng* rng);
// The family's example lens (LensFamilyInfo::example_lens), its focal length axis_focal_px times
// the family's example_focal_scale (about the same image size for every family), no skew.
CameraIntrinsics ExampleCamera(LensFamily family, double axis_focal_px, double u0_px, double v0_px);
// A uniformly random proper rotation (unit quaternion from four Gaussians).
Eigen::Matrix3d RandomRotation(Rng* rng);
Rigid3 RandomPose(double max_translation_m, Rng* rng);

// A planar calibration board seen from random viewpoints (classic camera calibration data).
struct SyntheticBoardOptions {
  int rows = 8, cols = 11;  // Corners.
  double spacing_m = 0.03;  // Corner pitch.
  int num_views = 20;
  double distance_m = 0.5;                    // Camera to board centre, +-20%.
  double max_tilt_deg = 40.0;                 // Board tilt about a random in-plane axis.
  double pixel_sigma_px = 0.0;                // Gaussian noise on u and v.
  int image_width = 640, image_height = 480;  // Views with a corner outside are redrawn.
};
struct SyntheticBoardViews {
  std::vector<View> views;             // Board frame points (z = 0) and pixels.
  std::vector<Rigid3> cam_from_board;  // Ground truth per view.
};
// cam_from_board of a board seen from the front (Kalibr's board frame: z towards the camera, x to
// the image's right, y up), turned by ExpSO3(tilt) in the board frame, with board point
// `board_point` at `point_in_cam`.
Rigid3 FacingBoardPose(const Eigen::Vector3d& tilt, const Eigen::Vector3d& board_point,
                       const Eigen::Vector3d& point_in_cam);
// The same board facing the camera centre from the direction of `ray` (any length; any direction
// but the backward axis, e.g. past 90 deg from the optical axis for an omnidirectional lens):
// FacingBoardPose's rotation turned by the rotation that takes the optical axis to `ray` about
// their common perpendicular, with `board_point` at `distance_m` along the ray. Seen from the
// camera it looks as a board facing it on the axis, turned with the line of sight.
Rigid3 FacingBoardPoseAlong(const Eigen::Vector3d& tilt, const Eigen::Vector3d& board_point,
                            const Eigen::Vector3d& ray, double distance_m);
// A random FacingBoardPoseAlong: the ray off_axis_deg from the optical axis at a uniform azimuth,
// the board tilted by up to max_tilt_deg about a uniform in-plane axis and turned by up to
// 0.5 rad about its normal, `board_point` at a distance uniform in [near_m, far_m]. Draws, in
// order: azimuth, tilt, tilt axis, turn, distance.
// The focal length (px) with which `lens`'s distortion images the ray `angle_deg` off the axis
// `radius_px` from the principal point (the lens's own focal lengths and principal point are not
// used): wide-lens scenes put the half field on a circle of the image with it. NaN where the lens
// does not image that ray.
double FocalLengthPuttingRayAt(CameraIntrinsics lens, double angle_deg, double radius_px);

struct FacingPoseRange {
  double max_tilt_deg = 35;
  double near_m = 0.3, far_m = 0.45;
};
Rigid3 RandomFacingBoardPose(const Eigen::Vector3d& board_point, double off_axis_deg,
                             const FacingPoseRange& range, Rng* rng);

// A planar board seen through a wide lens (120-200+ degrees) anywhere in its field, the edge of
// the image circle included: each view's board centre lies in a direction theta_c from the axis,
// theta_c = max_angle_deg sqrt(u) (u uniform: uniform over the disc of angles), azimuth uniform,
// at distance_m +- 20 %; the board faces the camera (FacingBoardPose turned onto that direction),
// tilted by up to max_tilt_deg about a random in-plane axis and rolled at random. Points outside
// the image or the lens' valid region are dropped (partial boards); a view is kept when at least
// min_visible_fraction of its points (and 8) remain, else redrawn.
struct WideBoardOptions {
  int rows = 6, cols = 8;   // Corners.
  double spacing_m = 0.04;  // Corner pitch.
  int num_views = 20;
  double distance_m = 0.4;
  double max_angle_deg = 90.0;
  double max_tilt_deg = 35.0;
  double min_visible_fraction = 0.5;
  double pixel_sigma_px = 0.0;  // Gaussian noise on u and v.
  int image_width = 1024, image_height = 1024;
};
SyntheticBoardViews MakeWideBoardViews(const CameraIntrinsics& intrinsics,
                                       const WideBoardOptions& options, Rng* rng);

// A 6 x 5 tag36h11 AprilGrid of 4 cm tags to render (cam_from_board left at identity).
BoardView SixByFiveTagGrid();

// Corners row by row: (c * spacing, r * spacing, 0).
std::vector<Eigen::Vector3d> BoardPoints(int rows, int cols, double spacing_m);
SyntheticBoardViews MakeBoardViews(const CameraIntrinsics& intrinsics,
                                   const SyntheticBoardOptions& options, Rng* rng);

}  // namespace calibench
