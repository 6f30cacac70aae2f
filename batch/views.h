// Lens models of the batch methods (the View type itself lives in core/view.h).
#pragma once

#include <string>
#include <vector>

#include "core/view.h"

namespace calibench {

// Lens models by the names the CLI and configs use:
//   pinhole (no distortion), pinhole-k2 (k1, k2), pinhole-radtan4 (k1, k2, p1, p2),
//   pinhole-radtan5 (k1, k2, p1, p2, k3).
enum class LensModel { kPinhole, kPinholeK2, kPinholeRadTan4, kPinholeRadTan5 };
const char* ToString(LensModel model);
bool ParseLensModel(const std::string& name, LensModel* model);
// Indices into PinholeSkewCamera's parameter array that stay fixed (phi: index 2 unless the skew
// is estimated; distortion terms the model lacks).
std::vector<int> FixedIntrinsics(LensModel model, bool estimate_skew);

}  // namespace calibench
