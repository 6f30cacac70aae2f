// libFuzzer target: Kalibr target YAML -> LoadTargetYamlFromString.
//
// Contract checked on every input: no crash, hang or leak; a refusal has a message naming the
// file; an accepted target is usable: an aprilgrid passes AprilGrid::Check and yields
// 4 x rows x cols finite corners, a checkerboard has >= 2 x 2 corners and positive spacings; and
// it writes back (TargetYamlText) to YAML that loads to the same target.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "fuzz/fuzz_check.h"
#include "io/target_io.h"

namespace {

void Check(bool ok, const char* what, const std::string& context = "") {
  calibench::FuzzRequire(ok, "target_yaml_fuzzer", what, context);
}

constexpr char kVirtualPath[] = "/nonexistent/fuzz/target.yaml";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string yaml(reinterpret_cast<const char*>(data), size);
  calibench::CalibrationTarget target;
  std::string why;
  if (!calibench::LoadTargetYamlFromString(yaml, kVirtualPath, &target, &why)) {
    Check(why.rfind(kVirtualPath, 0) == 0, "refusal does not name the file", why);
    return 0;
  }
  if (target.type == calibench::CalibrationTarget::Type::kAprilGrid) {
    Check(target.grid.Check(&why), "accepted an aprilgrid that fails Check", yaml);
    const auto corners = target.grid.CornersInBoard();
    Check(static_cast<long>(corners.size()) == 4L * target.grid.NumTags(), "corner count", yaml);
    for (const auto& c : corners) Check(c.allFinite(), "non-finite corner", yaml);
  } else {
    Check(target.cols >= 2 && target.rows >= 2, "checkerboard smaller than 2 x 2", yaml);
    Check(target.row_spacing_m > 0 && target.col_spacing_m > 0 &&
              std::isfinite(target.row_spacing_m) && std::isfinite(target.col_spacing_m),
          "checkerboard spacing not positive and finite", yaml);
  }
  calibench::CalibrationTarget again;
  const std::string written = calibench::TargetYamlText(target);
  Check(calibench::LoadTargetYamlFromString(written, kVirtualPath, &again, &why),
        "the written target YAML does not load", written + "\n" + why);
  const bool same =
      again.type == target.type && (target.type == calibench::CalibrationTarget::Type::kAprilGrid
                                        ? again.grid == target.grid
                                        : again.cols == target.cols && again.rows == target.rows &&
                                              again.row_spacing_m == target.row_spacing_m &&
                                              again.col_spacing_m == target.col_spacing_m);
  Check(same, "the written target YAML loads to another target", yaml + "\n->\n" + written);
  return 0;
}
