#include "sim/image_filters.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "util/random.h"

namespace calibench {
namespace {

// BlurNearBoardsAndSumBlocks against its definition, BlurNearBoards on the sub-pixels then
// SumBlocks: boards of random gray sub-pixels in a box on a uniform background, boxes inside the
// image and cut by each of its edges, grids m = 1..4 and several blurs. kRoundingTol: both sum
// ~(2 r + m)^2 float products of values <= 255 in another order: ~1e-5 relative.
TEST(ImageFilters, FusedBlurAndPixelSumEqualsTheTwoSteps) {
  constexpr double kRoundingTol = 2e-3;  // Gray levels.
  constexpr int kWidth = 37, kHeight = 23;
  Rng rng(11);
  const std::vector<std::array<int, 4>> pixel_boxes = {
      {10, 20, 8, 14}, {0, 12, 5, 9},  {25, 36, 3, 15}, {4, 30, 0, 6},
      {6, 18, 17, 22}, {0, 36, 0, 22}, {3, 2, 5, 9}};  // The last: no board in view.
  int compared = 0;
  for (int m = 1; m <= 4; ++m) {
    for (double sigma_px : {0.3, 0.5, 1.0}) {
      for (const auto& pb : pixel_boxes) {
        const int fw = kWidth * m, fh = kHeight * m;
        std::vector<float> fine(static_cast<size_t>(fw) * fh, 128.0f);
        // The box in sub-pixels, inclusive, as ShadePixels reports it.
        const std::array<int, 4> box = {pb[0] * m, pb[1] * m + m - 1, pb[2] * m, pb[3] * m + m - 1};
        for (int y = box[2]; y <= box[3]; ++y) {
          for (int x = box[0]; x <= box[1]; ++x) {
            fine[static_cast<size_t>(y) * fw + x] = static_cast<float>(rng.Uniform(20, 235));
          }
        }
        std::vector<float> expected, fused;
        std::vector<float> blurred = fine;
        BlurNearBoards(sigma_px * m, fw, fh, box, &blurred);
        SumBlocks(blurred, kWidth, kHeight, m, &expected);
        BlurNearBoardsAndSumBlocks(sigma_px * m, kWidth, kHeight, m, box, fine, &fused);
        ASSERT_EQ(fused.size(), expected.size());
        double worst = 0;
        for (size_t k = 0; k < fused.size(); ++k) {
          worst = std::max(worst, std::abs(static_cast<double>(fused[k]) - expected[k]));
        }
        EXPECT_LT(worst, kRoundingTol) << "m " << m << " sigma " << sigma_px << " box " << pb[0]
                                       << " " << pb[1] << " " << pb[2] << " " << pb[3];
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, 4 * 3 * 7);
}

}  // namespace
}  // namespace calibench
