// `calibench compare` (bench/app/compare_cmd.h).
#include "bench/app/compare_cmd.h"

#include <filesystem>
#include <iostream>

#include "calib/calibration_pictures.h"
#include "calib/compare_cameras.h"
#include "io/camera_io.h"

namespace calibench {

int Compare(const CompareArgs& args) {
  CameraFile a, b;
  std::string why;
  if (!ReadCameraFile(args.a_path, &a, &why) || !ReadCameraFile(args.b_path, &b, &why)) {
    std::cerr << "calibench: compare: " << why << "\n";
    return 2;
  }
  CompareOptions options;
  options.distance_m = args.distance_m;
  options.fit_rotation = !args.no_rotation;
  if (!options.Check(&why)) {
    std::cerr << "calibench: compare: " << why << "\n";
    return 2;
  }
  const std::string a_name = std::filesystem::path(args.a_path).filename().string();
  const std::string b_name = std::filesystem::path(args.b_path).filename().string();
  std::cout << "A: " << args.a_path << " (" << a.ModelName() << ", " << a.image_width << " x "
            << a.image_height << (a.projection.IsSet() ? ", with" : ", without")
            << " projection uncertainty)\n"
            << "B: " << args.b_path << " (" << b.ModelName() << ", " << b.image_width << " x "
            << b.image_height << (b.projection.IsSet() ? ", with" : ", without")
            << " projection uncertainty)\n";
  const CameraComparison c = CompareCameras(a, b, options);
  // A scaled copy is said by FormatComparison (b_scale); other sizes here.
  if ((a.image_width != b.image_width || a.image_height != b.image_height) && c.b_scale == 1.0) {
    std::cout << "note: the image sizes differ: compared over the pixels both images hold\n";
  }
  std::cout << FormatComparison(c, a_name, b_name);
  if (!c.ok) return 4;
  if (!args.out_path.empty()) {
    HeatmapOptions heat;
    heat.title = "Projection difference, " + b_name + " against " + a_name;
    if (!WriteHeatmapPng(args.out_path, c.difference_px, {}, heat, &why)) {
      std::cerr << "calibench: compare: --out: " << why << "\n";
      return 3;
    }
    std::cerr << "calibench: wrote " << args.out_path << "\n";
  }
  return c.verdict == CameraComparison::Verdict::kDiffer ? 1 : 0;
}

}  // namespace calibench
