// Every family of the list (camera/lens_families.h) through every camera file format that declares
// it (io/camera_io.h): opencv stores every family, kalibr those with a
// LensFamilyInfo::kalibr camera_model, mrcal those with mrcal_stores. A written file reads back to
// the same intrinsics; a format that does not declare the family refuses it, naming the family.
// Loops over LensFamilies(): a new family is tested without editing this file.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "io/camera_io.h"

namespace calibench {
namespace {

// The formats write 17 significant digits: a round trip is exact; 1e-12 relative is the bar.
constexpr double kRoundTripRelTol = 1e-12;

// The family's example lens (LensFamilyInfo::example_lens) without skew (Kalibr and mrcal have
// none) on a 960 x 600 image.
CameraFile Example(const LensFamilyInfo& info) {
  CameraFile camera;
  CameraIntrinsics& k = camera.intrinsics;
  k.family = info.family;
  k.fku_px = 330.25 * info.example_focal_scale;
  k.fkv_px = 331.5 * info.example_focal_scale;
  k.u0_px = 482.125;
  k.v0_px = 297.75;
  for (int i = 0; i < 5; ++i) {
    if (double* field = LensField(&k, info.lens_params[i])) *field = info.example_lens[i];
  }
  camera.lens_model = FullModelOf(info.family);
  camera.image_width = 960;
  camera.image_height = 600;
  camera.rms_reproj_px = 0.25;
  camera.intrinsics_std.fill(std::nan(""));
  return camera;
}

bool Declares(CameraFormat format, const LensFamilyInfo& info) {
  switch (format) {
    case CameraFormat::kOpenCv:
      return true;
    case CameraFormat::kKalibr:
      return info.kalibr.camera_model != nullptr;
    case CameraFormat::kMrcal:
      return info.mrcal_stores;
  }
  return false;
}

const char* Extension(CameraFormat format) {
  switch (format) {
    case CameraFormat::kOpenCv:
      return ".yaml";
    case CameraFormat::kKalibr:
      return "-camchain.yaml";
    case CameraFormat::kMrcal:
      return ".cameramodel";
  }
  return "";
}

TEST(LensFamilyCameraFiles, EveryDeclaredFormatRoundTripsEveryFamily) {
  int round_trips = 0;
  for (const LensFamilyInfo& info : LensFamilies()) {
    for (CameraFormat format :
         {CameraFormat::kOpenCv, CameraFormat::kKalibr, CameraFormat::kMrcal}) {
      SCOPED_TRACE(std::string(info.name) + " as " + ToString(format));
      const CameraFile camera = Example(info);
      std::string why;
      ASSERT_TRUE(camera.intrinsics.Check(&why)) << why;
      const std::string path = ::testing::TempDir() + "/lens_family_" + info.name + "_" +
                               ToString(format) + Extension(format);
      if (!Declares(format, info)) {
        EXPECT_FALSE(WriteCameraFile(path, format, camera, &why));
        EXPECT_NE(why.find(info.known_as), std::string::npos) << why;
        continue;
      }
      ASSERT_TRUE(WriteCameraFile(path, format, camera, &why)) << why;
      CameraFile back;
      ASSERT_TRUE(ReadCameraFile(path, &back, &why)) << why;
      EXPECT_EQ(back.intrinsics.family, info.family);
      const std::array<double, 10> want = camera.intrinsics.Params();
      const std::array<double, 10> got = back.intrinsics.Params();
      for (int i = 0; i < 10; ++i) {
        EXPECT_NEAR(got[i], want[i], kRoundTripRelTol * std::max(1.0, std::abs(want[i])))
            << ParamNames(info.family)[i];
      }
      EXPECT_EQ(back.image_width, 960);
      EXPECT_EQ(back.image_height, 600);
      ++round_trips;
    }
  }
  // opencv for every family, kalibr for the five of today, mrcal for radtan.
  EXPECT_GE(round_trips, 11);
}

}  // namespace
}  // namespace calibench
