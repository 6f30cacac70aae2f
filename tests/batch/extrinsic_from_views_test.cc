// batch/extrinsic_from_views.h: the constant extrinsic parent_from_cam from per-view board poses,
// by averaging (the board's place known) and by hand-eye (Tsai-Lenz's equations, the rotation as
// a unit quaternion; only the body motion known), against the swaying rig of sim/synthetic.h (a
// moving camera, board 0 fixed in the world, the body rotating about a wandering axis): exact on
// exact poses at any mount (the rig's own half-turn, where Tsai's own rotation step failed,
// included), errors consistent with the per-view errors when the poses come from noisy pixels
// (batch/board_pose.h), an estimate that turns with the frames, and the documented failures.
#include "batch/extrinsic_from_views.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "batch/board_pose.h"
#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

double RotationErrorRad(const Rigid3& a, const Rigid3& b) {
  return Eigen::AngleAxisd(a.rotation * b.rotation.transpose()).angle();
}
Eigen::Vector3d RotationErrorVector(const Rigid3& a, const Rigid3& b) {
  const Eigen::AngleAxisd e(a.rotation * b.rotation.transpose());
  return e.angle() * e.axis();
}

// The rig's views of board 0: every 0.5 s over 30 s, the body poses (parent = body, points frame =
// world: parent_from_points = body_from_world), the board's pose in the body (known for
// averaging) and the exact cam_from_board. The rig's R_C is a half-turn about u = (0, 1, 1) /
// sqrt 2, where Tsai's own parametrisation (tan(theta / 2) axis) is infinite. The body frame is
// re-expressed by a fixed rotation S = Exp(-back_rad u) (parent' = S parent), which leaves the
// camera, the board and every cam_from_board as they are and makes the mount a turn of pi -
// back_rad about u: the default 1 rad gives 123 deg (a generic mount), 0 the rig's own half-turn.
struct RigViews {
  Rigid3 parent_from_cam;  // The truth, X.
  PlanarBoard board;
  CameraIntrinsics intrinsics;
  std::vector<double> times;
  std::vector<Rigid3> parent_from_points, parent_from_board, cam_from_board;
};
RigViews MakeRigViews(int views = 60, double back_rad = 1.0) {
  const BoardRigScene rig = SwayingBoardRig();
  const Rigid3 s{ExpSO3(-back_rad * Eigen::Vector3d(0, 1, 1).normalized()),
                 Eigen::Vector3d::Zero()};
  RigViews r;
  r.parent_from_cam = s * rig.scene.parent_from_cam;
  r.board = rig.boards[0];
  r.intrinsics = rig.scene.intrinsics;
  for (int v = 0; v < views; ++v) {
    const double t = 0.5 * (v + 1);
    r.times.push_back(t);
    r.parent_from_points.push_back(s * rig.scene.ParentFromPoints(t));
    r.parent_from_board.push_back(r.parent_from_points.back() * r.board.points_from_board);
    r.cam_from_board.push_back(r.parent_from_cam.Inverse() * r.parent_from_board.back());
  }
  return r;
}
double MountDeg(const RigViews& r) {
  return Eigen::AngleAxisd(r.parent_from_cam.rotation).angle() * 180 / M_PI;
}

// cam_from_board from 0.2 px pixels of the board's 88 corners (BoardPoseFromIntrinsics through the
// rig's camera), one pose per view of `r`.
std::vector<Rigid3> NoisyCamFromBoard(const RigViews& r, Rng* rng) {
  constexpr double kPixelSigmaPx = 0.2;
  std::vector<Rigid3> poses;
  const std::vector<Eigen::Vector3d> corners = r.board.CornersInBoard();
  for (const Rigid3& cam_from_board : r.cam_from_board) {
    View view;
    for (const Eigen::Vector3d& p : corners) {
      Eigen::Vector2d pixel;
      EXPECT_TRUE(ProjectPoint(r.intrinsics, cam_from_board * p, &pixel));
      view.points.push_back(p);
      view.pixels.push_back(pixel + kPixelSigmaPx * NormalPair<Eigen::Vector2d>(rng));
    }
    Rigid3 pose;
    std::string why;
    EXPECT_TRUE(BoardPoseFromIntrinsics(view, r.intrinsics, &pose, &why)) << why;
    poses.push_back(pose);
  }
  return poses;
}

// Exact poses: both give X to rounding. The averaging sums 60 rotations (each X to ~1e-16) and
// projects with an SVD; hand-eye solves two small linear least-squares problems (rotation by an
// SVD, then translation by QR) on the relative motions of the 1770 pairs of views. Measured:
// averaging 2.5e-16 rad, 1.0e-14 m; hand-eye at most 2.1e-15 rad, 7.6e-15 m (at the mounts of
// ExactPosesGiveTheExtrinsicAtAnyMount). kExact* allow ~100x that, and are 1e9 times below the
// errors a wrong frame convention gives (radians, metres).
constexpr double kExactRad = 1e-12, kExactM = 1e-12;

TEST(AveragePoses, ExactPosesGiveTheExtrinsic) {
  // Reframed too: the rig's own R_C (a half-turn) is symmetric, blind to a transposed rotation.
  const RigViews r = MakeRigViews();
  std::vector<Rigid3> per_view;
  for (size_t v = 0; v < r.times.size(); ++v) {
    per_view.push_back(r.parent_from_board[v] * r.cam_from_board[v].Inverse());
  }
  const Rigid3 mean = AveragePoses(per_view);
  EXPECT_LT(RotationErrorRad(mean, r.parent_from_cam), kExactRad);
  EXPECT_LT((mean.translation - r.parent_from_cam.translation).norm(), kExactM);
}

// The chordal L2 mean of Exp(w) R and Exp(-w) R is R exactly (their sum is 2 (I + (1 - cos|w|)
// K^2) R with K = Hat(w / |w|), a positive-definite symmetric factor for |w| < 90 deg, which the
// SO(3) projection drops); their positions average to the midpoint. 30 deg apart, not small.
TEST(AveragePoses, ASymmetricPairAveragesToItsMiddle) {
  Rng rng(21);
  const Eigen::Matrix3d r = RandomRotation(&rng);
  const Eigen::Vector3d w = Eigen::Vector3d(0.3, -0.5, 0.8).normalized() * 30 * M_PI / 180;
  const Rigid3 mean = AveragePoses(
      {{ExpSO3(w) * r, Eigen::Vector3d(1, 2, 3)}, {ExpSO3(-w) * r, Eigen::Vector3d(-1, 0, 5)}});
  EXPECT_LT(RotationErrorRad(mean, {r, Eigen::Vector3d::Zero()}), 1e-14);  // ~10 ulp of 1.
  EXPECT_LT((mean.translation - Eigen::Vector3d(0, 1, 4)).norm(), 1e-15);
  // Mutation checked: AveragePoses summing rotation.transpose() (2 rad off) or returning the first
  // pose both fail here (and in the noisy test below).
}

// Exact poses at the mounts that matter: generic (123 deg), the rig's own half-turn (180 deg, where
// Tsai's own rotation step returned X pi off, 2.6 m, with no error), next to it (179 deg) and
// none (0 deg); then a half-turn about another axis (x). Each is X to rounding (kExact*).
TEST(HandEyeTsai, ExactPosesGiveTheExtrinsicAtAnyMount) {
  for (const double back_rad : {1.0, 0.0, M_PI / 180, M_PI}) {
    const RigViews r = MakeRigViews(60, back_rad);
    SCOPED_TRACE("mount " + std::to_string(MountDeg(r)) + " deg");
    Rigid3 x;
    std::string why;
    ASSERT_TRUE(HandEyeTsai(r.parent_from_points, r.cam_from_board, &x, &why)) << why;
    EXPECT_LT(RotationErrorRad(x, r.parent_from_cam), kExactRad);
    EXPECT_LT((x.translation - r.parent_from_cam.translation).norm(), kExactM);
  }
  // The rig's half-turn re-expressed as a half-turn about x: parent' = S parent with S = Rx(pi)
  // R_C^T.
  RigViews r = MakeRigViews(60, 0.0);
  const Rigid3 s{ExpSO3(Eigen::Vector3d(M_PI, 0, 0)) * r.parent_from_cam.rotation.transpose(),
                 Eigen::Vector3d(0.3, -0.2, 0.1)};
  r.parent_from_cam = s * r.parent_from_cam;
  for (Rigid3& p : r.parent_from_points) p = s * p;
  ASSERT_NEAR(MountDeg(r), 180.0, 1e-6);
  Rigid3 x;
  std::string why;
  ASSERT_TRUE(HandEyeTsai(r.parent_from_points, r.cam_from_board, &x, &why)) << why;
  EXPECT_LT(RotationErrorRad(x, r.parent_from_cam), kExactRad);
  EXPECT_LT((x.translation - r.parent_from_cam.translation).norm(), kExactM);
  // Mutation checked: A = P_j^-1 P_i (the other convention: 1.9-2.8 rad off at every mount) and
  // t_A added instead of subtracted in the translation step (0.04-0.7 m) fail here.
}

// Body poses at random (uniform rotations, so pairs of views turn by anything up to 180 deg): the
// sign pairing of q_A with q_B (w >= 0) is exercised past 120 deg, where Eigen's quaternion of a
// matrix has either sign (123 of the 405 pairs here), and the 30 of the 435 pairs turning more than
// kHandEyeMaxPairTurnDeg are left out. Exact poses: X to rounding (measured 6e-16 rad, 1.1e-15 m),
// at the rig's half-turn mount and at a generic one. (Mutation note: without the sign flip of q_A
// it still passes: a mismatched pair's residual is largest at the true q_X, which stays a
// stationary point and here the minimum; with 1e-3 rad, 1 mm pose noise its errors grew 1.5x.)
TEST(HandEyeTsai, LargeRelativeTurnsGiveTheExtrinsic) {
  Rng rng(24);
  const Rigid3 points_from_board{RandomRotation(&rng), Eigen::Vector3d(0.3, 1.5, -0.2)};
  std::vector<Rigid3> parent_from_points;
  parent_from_points.reserve(30);
  int beyond = 0;
  for (int v = 0; v < 30; ++v) {
    const Eigen::Matrix3d rotation = RandomRotation(&rng);
    const double z = rng.Normal(), y = rng.Normal();  // Last first (util/random.h).
    parent_from_points.push_back({rotation, Eigen::Vector3d(rng.Normal(), y, z)});
  }
  for (int i = 0; i < 30; ++i) {
    for (int j = i + 1; j < 30; ++j) {
      const double turn_deg =
          RotationAngleDeg(parent_from_points[j].rotation, parent_from_points[i].rotation);
      beyond += turn_deg > kHandEyeMaxPairTurnDeg;
    }
  }
  EXPECT_GT(beyond, 0);  // The exclusion is exercised (30 of 435 here).
  for (const double back_rad : {0.0, 1.0}) {
    const Rigid3 x_true = MakeRigViews(1, back_rad).parent_from_cam;
    std::vector<Rigid3> cam_from_board;
    cam_from_board.reserve(parent_from_points.size());
    for (const Rigid3& p : parent_from_points)
      cam_from_board.push_back(x_true.Inverse() * p * points_from_board);
    Rigid3 x;
    std::string why;
    ASSERT_TRUE(HandEyeTsai(parent_from_points, cam_from_board, &x, &why)) << why;
    EXPECT_LT(RotationErrorRad(x, x_true), kExactRad);
    EXPECT_LT((x.translation - x_true.translation).norm(), kExactM);
  }
}

// Noisy poses: cam_from_board from 0.2 px pixels (NoisyCamFromBoard). Each view then gives
// parent_from_cam_v with an error e_v (rotation vector, position) independent of the others' and
// ~zero-mean; the average's error is their mean, to first order, with E|mean|^2 = E|e|^2 / N.
// Bound: kSigmas times the views' measured RMS error over sqrt(N) (|mean|^2 > 16 E|e|^2 / N is a
// chi^2_3 > 48 event for isotropic Gaussian errors: < 1e-9; anisotropic errors make it likelier,
// but not beyond Markov's 1 / 16). Hand-eye uses only relative motions (differences of two views'
// poses) and is less efficient: kHandEyeFactor allows it 3x the averaging's bound (12x RMS /
// sqrt(N)). Measured: per view 2.8e-3 rad, 10 mm; averaged 1.4e-4 rad, 0.44 mm (0.4x, 0.3x the
// RMS / sqrt(N)); hand-eye 9.8e-4 rad, 3.7 mm (2.7x, 2.7x). At the generic and the half-turn mount
// alike: the same pixels, and the same errors, as the estimate does not depend on the parent
// frame (TheEstimateTurnsWithItsFrames); Tsai's own rotation step, on 40 such noise draws, had a
// median error of 0.09 rad at 180 deg (RMS 0.65 rad) and 2.0e-3 rad at 179 deg, against 7.0e-4
// rad for this one at every mount (and 6.8e-4 - 7.6e-4 for Tsai's at 90 - 151 deg).
TEST(ExtrinsicFromViews, NoisyPosesGiveErrorsConsistentWithThePerViewErrors) {
  constexpr double kSigmas = 4.0, kHandEyeFactor = 3.0;
  for (const double back_rad : {1.0, 0.0}) {
    const RigViews r = MakeRigViews(60, back_rad);
    SCOPED_TRACE("mount " + std::to_string(MountDeg(r)) + " deg");
    const int n = static_cast<int>(r.times.size());
    Rng rng(22);
    const std::vector<Rigid3> noisy_cam_from_board = NoisyCamFromBoard(r, &rng);
    std::vector<Rigid3> per_view;
    double sum_sq_rad = 0, sum_sq_m = 0;
    for (int v = 0; v < n; ++v) {
      per_view.push_back(r.parent_from_board[v] * noisy_cam_from_board[v].Inverse());
      sum_sq_rad += RotationErrorVector(per_view.back(), r.parent_from_cam).squaredNorm();
      sum_sq_m += (per_view.back().translation - r.parent_from_cam.translation).squaredNorm();
    }
    const double bound_rad = kSigmas * std::sqrt(sum_sq_rad / n) / std::sqrt(n);
    const double bound_m = kSigmas * std::sqrt(sum_sq_m / n) / std::sqrt(n);

    const Rigid3 mean = AveragePoses(per_view);
    const double mean_rad = RotationErrorRad(mean, r.parent_from_cam);
    const double mean_m = (mean.translation - r.parent_from_cam.translation).norm();
    Rigid3 x;
    std::string why;
    ASSERT_TRUE(HandEyeTsai(r.parent_from_points, noisy_cam_from_board, &x, &why)) << why;
    const double tsai_rad = RotationErrorRad(x, r.parent_from_cam);
    const double tsai_m = (x.translation - r.parent_from_cam.translation).norm();
    EXPECT_LT(mean_rad, bound_rad);
    EXPECT_LT(mean_m, bound_m);
    EXPECT_LT(tsai_rad, kHandEyeFactor * bound_rad);
    EXPECT_LT(tsai_m, kHandEyeFactor * bound_m);
  }
  // Mutation checked: AveragePoses returning the first view's pose (error 1.9e-3 rad >
  // bound 1.4e-3) fails here.
}

// The estimate does not depend on the frames the poses are written in: re-expressing the parent
// frame by a rigid motion S (P_v' = S P_v) and the camera frame by a rotation U (C_v' = U C_v)
// gives S X U^-1, on noisy poses too: every pair's quaternion residual is multiplied by q_S on the
// left and q_U^-1 on the right, which keeps its norm, and the translation residuals are turned by
// R_S. (A camera frame moved by t_U would add (R_A R_X - R_X R_B) R_U^T t_U to them: zero only for
// exact rotations.) Measured 1.6e-15 rad; Tsai's own rotation step (w_X fixed to 1) moved by noise
// amounts. S, U: generic turns of 2.0 and 2.5 rad.
TEST(HandEyeTsai, TheEstimateTurnsWithItsFrames) {
  const RigViews r = MakeRigViews(60, 0.0);
  Rng rng(23);
  const std::vector<Rigid3> c = NoisyCamFromBoard(r, &rng);
  const Rigid3 s{ExpSO3(Eigen::Vector3d(0.8, -1.2, 1.4).normalized() * 2.0),
                 Eigen::Vector3d(0.5, -1, 2)};
  const Rigid3 u{ExpSO3(Eigen::Vector3d(-0.3, 0.9, 0.2).normalized() * 2.5),
                 Eigen::Vector3d::Zero()};
  std::vector<Rigid3> p2, c2;
  for (size_t v = 0; v < c.size(); ++v) {
    p2.push_back(s * r.parent_from_points[v]);
    c2.push_back(u * c[v]);
  }
  Rigid3 x, x2;
  std::string why;
  ASSERT_TRUE(HandEyeTsai(r.parent_from_points, c, &x, &why)) << why;
  ASSERT_TRUE(HandEyeTsai(p2, c2, &x2, &why)) << why;
  const Rigid3 expected = s * x * u.Inverse();
  EXPECT_LT(RotationErrorRad(x2, expected), kExactRad);
  EXPECT_LT((x2.translation - expected.translation).norm(), kExactM);
}

TEST(HandEyeTsai, SingleAxisOrNoMotionIsRefusedWithAReason) {
  const RigViews r = MakeRigViews(20);
  // The body turning about its z axis only (and moving): Tsai cannot fix the rotation about it.
  std::vector<Rigid3> single_axis, still, cam_from_board;
  const Rigid3 world_from_board = r.parent_from_points[0].Inverse() * r.parent_from_board[0];
  for (int v = 0; v < 20; ++v) {
    single_axis.push_back(
        {ExpSO3(Eigen::Vector3d(0, 0, 0.05 * v)), Eigen::Vector3d(0.01 * v, 0, 0)});
    still.push_back(r.parent_from_points[0]);
  }
  for (const std::vector<Rigid3>* motion : {&single_axis, &still}) {
    cam_from_board.clear();
    for (const Rigid3& p : *motion) {
      cam_from_board.push_back(r.parent_from_cam.Inverse() * p * world_from_board);
    }
    Rigid3 x;
    std::string why;
    EXPECT_FALSE(HandEyeTsai(*motion, cam_from_board, &x, &why));
    EXPECT_NE(why.find("degenerate"), std::string::npos) << why;
  }
}

// Fewer than 3 views (matched lists).
TEST(HandEyeTsai, FewerThanThreeViewsAreRefusedWithAReason) {
  const RigViews r = MakeRigViews(20);
  Rigid3 x;
  std::string why;
  EXPECT_FALSE(HandEyeTsai({r.parent_from_points[0], r.parent_from_points[5]},
                           {r.cam_from_board[0], r.cam_from_board[5]}, &x, &why));
  EXPECT_NE(why.find("at least 3 views"), std::string::npos) << why;
  why.clear();
  EXPECT_FALSE(HandEyeTsai({}, {}, &x, &why));
  EXPECT_NE(why.find("at least 3 views"), std::string::npos) << why;
  // Three views about two axes suffice (the minimum is not off by one).
  ASSERT_TRUE(
      HandEyeTsai({r.parent_from_points[0], r.parent_from_points[6], r.parent_from_points[12]},
                  {r.cam_from_board[0], r.cam_from_board[6], r.cam_from_board[12]}, &x, &why))
      << why;
  EXPECT_LT(RotationErrorRad(x, r.parent_from_cam), kExactRad);
}

// The i-th body pose goes with the i-th board pose: lists of different lengths are refused, more
// board poses than body poses too (it used to read past the body poses' end).
TEST(HandEyeTsai, ListsOfDifferentLengthsAreRefusedWithAReason) {
  const RigViews r = MakeRigViews(20);
  const std::vector<Rigid3> two_boards{r.cam_from_board[0], r.cam_from_board[1]};
  const std::vector<Rigid3> two_bodies{r.parent_from_points[0], r.parent_from_points[1]};
  Rigid3 x;
  std::string why;
  EXPECT_FALSE(HandEyeTsai(r.parent_from_points, two_boards, &x, &why));
  EXPECT_NE(why.find("20 body poses and 2 board poses"), std::string::npos) << why;
  why.clear();
  EXPECT_FALSE(HandEyeTsai(two_bodies, r.cam_from_board, &x, &why));
  EXPECT_NE(why.find("2 body poses and 20 board poses"), std::string::npos) << why;
  why.clear();
  EXPECT_FALSE(HandEyeTsai({}, r.cam_from_board, &x, &why));
  EXPECT_NE(why.find("one body pose per board pose"), std::string::npos) << why;
}

// A non-finite pose is refused, naming its view; so are views whose every pair turns by a
// half-turn (I, Rx(pi), Ry(pi): the pairs turn about x, y and z, two axes between neighbours, but
// all beyond kHandEyeMaxPairTurnDeg, where the sign pairing of their quaternions is noise).
TEST(HandEyeTsai, NonFiniteOrHalfTurnOnlyViewsAreRefusedWithAReason) {
  RigViews r = MakeRigViews(20);
  r.cam_from_board[4].translation.y() = std::numeric_limits<double>::quiet_NaN();
  Rigid3 x;
  std::string why;
  EXPECT_FALSE(HandEyeTsai(r.parent_from_points, r.cam_from_board, &x, &why));
  EXPECT_NE(why.find("view 4 are not finite"), std::string::npos) << why;
  const std::vector<Rigid3> half_turns{
      {Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0)},
      {ExpSO3(Eigen::Vector3d(M_PI, 0, 0)), Eigen::Vector3d(0.1, 0, 0)},
      {ExpSO3(Eigen::Vector3d(0, M_PI, 0)), Eigen::Vector3d(0, 0.1, 0)}};
  std::vector<Rigid3> cam_from_board;
  cam_from_board.reserve(half_turns.size());
  for (const Rigid3& p : half_turns) cam_from_board.push_back(r.parent_from_cam.Inverse() * p);
  why.clear();
  EXPECT_FALSE(HandEyeTsai(half_turns, cam_from_board, &x, &why));
  EXPECT_NE(why.find("do not fix the camera's rotation"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
