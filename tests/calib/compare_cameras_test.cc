// Two calibrations compared (calib/compare_cameras.h) against cases whose answer is known: a
// camera against itself turned, against its own projection in another lens family, against a
// principal point moved by more than the uncertainty, at different image sizes, and without
// uncertainty.
#include "calib/compare_cameras.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "camera/pose.h"

namespace calibench {
namespace {

// Rays through two models of one camera differ by rounding only: 1e-9 px at 1000 px.
constexpr double kSameCameraPx = 1e-6;
// A rotation fitted to identical rays: rounding, 1e-9 deg.
constexpr double kRotationTolDeg = 1e-6;

CameraFile Camera(double fku, double u0) {
  CameraFile c;
  c.intrinsics = {fku, fku * 1.001, 90.0, u0, 241.0, -0.22, 0.06};
  c.lens_model = LensModel::kPinholeK2;
  c.image_width = 640, c.image_height = 480;
  return c;
}

// An uncertainty of about `sigma_px` at the image centre: the principal point's and the focal
// length's variances (z's u0, v0, fku, fkv) only.
void SetUncertainty(double sigma_px, CameraFile* c) {
  c->projection.covariance.setZero();
  for (int i : {0, 1}) c->projection.covariance(i, i) = 4 * sigma_px * sigma_px;
  for (int i : {3, 4}) c->projection.covariance(i, i) = sigma_px * sigma_px;
  c->projection.num_views = 10;
  c->projection.sigma_px = 0.2;
}

TEST(CompareCameras, ACameraAgainstItselfIsTheSame) {
  CameraFile a = Camera(520, 322);
  SetUncertainty(0.1, &a);
  const CameraComparison c = CompareCameras(a, a, {});
  ASSERT_TRUE(c.ok) << c.message;
  EXPECT_LT(c.max_px, kSameCameraPx);
  EXPECT_LT(c.rotation_deg, kRotationTolDeg);
  EXPECT_EQ(c.verdict, CameraComparison::Verdict::kAgree);
  EXPECT_DOUBLE_EQ(c.common_fraction, 1.0);
}

TEST(CompareCameras, AFrameRotationIsFittedOut) {
  // B is A with its principal point moved by f * 0.002 rad horizontally: to first order a yaw of
  // the camera frame, which the fit takes out down to the lens's second-order terms.
  const CameraFile a = Camera(520, 322);
  CameraFile b = a;
  b.intrinsics.u0_px += 520 * 0.002;
  CompareOptions fixed;
  fixed.fit_rotation = false;
  const CameraComparison raw = CompareCameras(a, b, fixed);
  const CameraComparison fitted = CompareCameras(a, b, {});
  ASSERT_TRUE(raw.ok && fitted.ok);
  EXPECT_NEAR(raw.median_px, 1.04, 0.05);  // The shift itself, ~uniform.
  // The shift equals a yaw at the centre only (off the centre a yaw moves a pixel by
  // f (1 + x^2) theta, and the lens bends it): the fitted angle within 5 % of 0.002 rad.
  EXPECT_NEAR(fitted.rotation_deg, 0.002 * 180 / M_PI, 0.05 * 0.002 * 180 / M_PI);
  EXPECT_LT(fitted.median_px, 0.1 * raw.median_px);
  EXPECT_EQ(fitted.verdict, CameraComparison::Verdict::kNoUncertainty);
}

TEST(CompareCameras, AShiftBeyondTheUncertaintyDiffersAndOneWithinAgrees) {
  // A focal length change cannot be rotated away: 1 % of 520 px is 2.6 px at 250 px from the
  // centre.
  CameraFile a = Camera(520, 322);
  CameraFile b = Camera(525.2, 322);
  SetUncertainty(0.1, &a);
  SetUncertainty(0.1, &b);
  const CameraComparison tight = CompareCameras(a, b, {});
  ASSERT_TRUE(tight.ok);
  EXPECT_EQ(tight.verdict, CameraComparison::Verdict::kDiffer);
  EXPECT_LT(tight.within_fraction, kAgreeFraction);
  SetUncertainty(3.0, &a);
  SetUncertainty(3.0, &b);
  const CameraComparison loose = CompareCameras(a, b, {});
  EXPECT_EQ(loose.verdict, CameraComparison::Verdict::kAgree);
  EXPECT_GE(loose.within_fraction, kAgreeFraction);
}

TEST(CompareCameras, DifferentImageSizesCompareOverTheCommonPixels) {
  const CameraFile a = Camera(520, 322);
  CameraFile b = a;
  b.image_width = 320;  // The left half of A's pixels.
  const CameraComparison c = CompareCameras(a, b, {});
  ASSERT_TRUE(c.ok) << c.message;
  EXPECT_NEAR(c.common_fraction, 0.5, 0.02);
  EXPECT_LT(c.max_px, kSameCameraPx);
}

TEST(CompareCameras, AnotherFamilyFittedToTheSameLensIsClose) {
  // Double sphere with alpha = 0, xi = 0 is a pinhole: the same rays as radtan without distortion.
  CameraFile a = Camera(520, 322);
  a.intrinsics.k1 = a.intrinsics.k2 = 0;
  CameraFile b = a;
  b.intrinsics = CameraIntrinsics();
  b.intrinsics.family = LensFamily::kDoubleSphere;
  b.intrinsics.fku_px = a.intrinsics.fku_px, b.intrinsics.fkv_px = a.intrinsics.fkv_px;
  b.intrinsics.u0_px = a.intrinsics.u0_px, b.intrinsics.v0_px = a.intrinsics.v0_px;
  b.intrinsics.xi = 0, b.intrinsics.alpha = 0;
  b.lens_model = LensModel::kDoubleSphere;
  const CameraComparison c = CompareCameras(a, b, {});
  ASSERT_TRUE(c.ok) << c.message;
  EXPECT_LT(c.max_px, kSameCameraPx);
}

TEST(CompareCameras, OneUncertaintyJudgesAloneAndNoneGivesTheDifferenceOnly) {
  CameraFile a = Camera(520, 322);
  const CameraFile b = Camera(521, 322);  // 0.5 px at 250 px from the centre.
  SetUncertainty(1.0, &a);
  const CameraComparison one = CompareCameras(a, b, {});
  ASSERT_TRUE(one.ok);
  EXPECT_EQ(one.verdict, CameraComparison::Verdict::kAgree);
  const std::string text = FormatComparison(one, "a.yaml", "b.cameramodel");
  EXPECT_NE(text.find("AGREE within a.yaml's uncertainty alone (b.cameramodel carries none)"),
            std::string::npos)
      << text;
  const CameraComparison none = CompareCameras(Camera(520, 322), b, {});
  ASSERT_TRUE(none.ok);
  EXPECT_EQ(none.verdict, CameraComparison::Verdict::kNoUncertainty);
  EXPECT_NE(FormatComparison(none, "a", "b").find("difference only"), std::string::npos);
}

TEST(CompareCameras, AScaledCopyIsTakenToThePixelsOfTheOther) {
  // TUM VI's case: a camera published at half the resolution of the frames.
  CameraFile a = Camera(520, 322);
  SetUncertainty(0.2, &a);
  CameraFile half = ScaleCamera(a, 0.5);
  EXPECT_DOUBLE_EQ(half.intrinsics.u0_px, 0.5 * (322 + 0.5) - 0.5);
  EXPECT_EQ(half.image_width, 320);
  const CameraComparison c = CompareCameras(a, half, {});
  ASSERT_TRUE(c.ok) << c.message;
  EXPECT_DOUBLE_EQ(c.b_scale, 2.0);
  EXPECT_LT(c.max_px, kSameCameraPx);
  EXPECT_DOUBLE_EQ(c.common_fraction, 1.0);
  // The covariance goes along: at the same point of the image, half the pixels' sigma.
  for (const Eigen::Vector2d& q : {Eigen::Vector2d(320, 240), Eigen::Vector2d(40, 400)}) {
    PixelUncertainty full_u, half_u;
    const double inf = std::numeric_limits<double>::infinity();
    ASSERT_TRUE(ProjectionUncertaintyAt(a.intrinsics, a.projection, q, inf, &full_u, nullptr));
    ASSERT_TRUE(ProjectionUncertaintyAt(
        half.intrinsics, half.projection,
        0.5 * (q + Eigen::Vector2d(0.5, 0.5)) - Eigen::Vector2d(0.5, 0.5), inf, &half_u, nullptr));
    EXPECT_NEAR(half_u.worst_std_px, 0.5 * full_u.worst_std_px, 1e-9 * full_u.worst_std_px);
  }
}

TEST(CompareCameras, CamerasWithoutCommonFieldAreRefused) {
  CameraFile a = Camera(520, 322);
  CameraFile b = a;
  b.image_width = 0;
  EXPECT_FALSE(CompareCameras(a, b, {}).ok);
  CompareOptions bad;
  bad.distance_m = -1;
  const CameraComparison c = CompareCameras(a, a, bad);
  EXPECT_FALSE(c.ok);
  EXPECT_NE(c.message.find("distance"), std::string::npos) << c.message;
}

}  // namespace
}  // namespace calibench
