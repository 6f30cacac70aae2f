// calibrate's built-in cross-validation: the views split in two halves (alternately: even and odd
// positions among the views used, so each half spans the session), each half calibrated alone
// with the same options (its own jackknife and projection uncertainty), and the two cameras
// compared over the image (calib/compare_cameras.h). Two calibrations from disjoint data should
// differ by about their combined uncertainty (mrcal's cross-validation); a larger difference is
// a lens model that does not fit or views that disagree, and it names where.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "calib/calibrate_camera.h"
#include "calib/compare_cameras.h"

namespace calibench {

struct CrossValidation {
  bool ok = false;
  std::string message;  // Why not ok (too few views, a half that does not calibrate).
  std::array<CameraFile, 2> halves;
  std::array<int, 2> half_views{};
  CameraComparison comparison;  // halves[1] against halves[0].
};

// Needs at least 2 * kMinViewsPerHalf used views in a usable `result`; `options` are those it was
// calibrated with (the model it fitted is result.model).
constexpr int kMinViewsPerHalf = 3;
CrossValidation CrossValidate(const CalibrateResult& result, const CalibrateOptions& options);

std::string FormatCrossValidation(const CrossValidation& cv);

}  // namespace calibench
