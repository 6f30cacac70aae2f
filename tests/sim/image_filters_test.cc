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

// AddImageNoise has no pattern common to frames: over kFrames frames (rng seeds 1..kFrames) of
// kWidth x kHeight unit-sigma noise, every column's and every row's mean is N(0, 1 / n) for an iid
// field (n = the draws it averages), so sum(n mean^2) over the columns (rows) is chi-square with
// kWidth (kHeight) degrees of freedom; bounded by its quantile of probability 0.9999
// (Wilson-Hilferty). A table read from each block's start fails this: every frame's column x then
// holds entry x of some block, whose mean over the table's B blocks is a fixed N(0, 1 / B), and
// the column statistic is ~ (1 + n / B) kWidth (8.8 kWidth here for B = 4096).
TEST(ImageFilters, NoiseHasNoPatternCommonToFrames) {
  constexpr int kFrames = 500, kWidth = 300, kHeight = 64;
  std::vector<double> column_sum(kWidth, 0.0), row_sum(kHeight, 0.0);
  std::vector<float> frame;
  for (int f = 1; f <= kFrames; ++f) {
    frame.assign(static_cast<size_t>(kWidth) * kHeight, 0.0f);
    Rng rng(f);
    AddImageNoise(1.0, kWidth, kHeight, &rng, &frame);
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        const double v = frame[static_cast<size_t>(y) * kWidth + x];
        column_sum[x] += v, row_sum[y] += v;
      }
    }
  }
  auto chi_square = [](const std::vector<double>& sums, double n) {
    double s = 0;
    for (double sum : sums) s += sum * sum / n;
    return s;
  };
  auto quantile_9999 = [](int dof) {  // Wilson-Hilferty, normal quantile 3.719.
    const double a = 2.0 / (9.0 * dof);
    return dof * std::pow(1 - a + 3.719 * std::sqrt(a), 3);
  };
  EXPECT_LT(chi_square(column_sum, double{kFrames} * kHeight), quantile_9999(kWidth));
  EXPECT_LT(chi_square(row_sum, double{kFrames} * kWidth), quantile_9999(kHeight));
  // And the noise is unit-sigma: the last frame's variance within 5 std of an iid one's (the
  // variance of a sample variance of n unit normals is 2 / n).
  double sum2 = 0;
  for (float v : frame) sum2 += double{v} * v;
  EXPECT_NEAR(sum2 / frame.size(), 1.0, 5 * std::sqrt(2.0 / frame.size()));
}

}  // namespace
}  // namespace calibench
