#include "batch/views.h"

namespace calibench {

const char* ToString(LensModel model) {
  switch (model) {
    case LensModel::kPinhole:
      return "pinhole";
    case LensModel::kPinholeK2:
      return "pinhole-k2";
    case LensModel::kPinholeRadTan4:
      return "pinhole-radtan4";
    case LensModel::kPinholeRadTan5:
      return "pinhole-radtan5";
  }
  return "pinhole";
}

bool ParseLensModel(const std::string& name, LensModel* model) {
  for (LensModel m : {LensModel::kPinhole, LensModel::kPinholeK2, LensModel::kPinholeRadTan4,
                      LensModel::kPinholeRadTan5}) {
    if (name == ToString(m)) {
      *model = m;
      return true;
    }
  }
  return false;
}

std::vector<int> FixedIntrinsics(LensModel model, bool estimate_skew) {
  std::vector<int> fixed;
  if (!estimate_skew) fixed.push_back(2);
  switch (model) {
    case LensModel::kPinhole:
      fixed.insert(fixed.end(), {5, 6, 7, 8, 9});
      break;
    case LensModel::kPinholeK2:
      fixed.insert(fixed.end(), {7, 8, 9});
      break;
    case LensModel::kPinholeRadTan4:
      fixed.push_back(9);
      break;
    case LensModel::kPinholeRadTan5:
      break;
  }
  return fixed;
}

}  // namespace calibench
