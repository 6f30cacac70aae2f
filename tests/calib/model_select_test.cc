// calibrate --model auto (calib/model_select.h) on synthetic data: the pick is within noise of
// the truth's family, and the table says why.
#include "calib/model_select.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

PointData Points(const SyntheticBoardViews& data, int side) {
  PointData points;
  points.format = "synthetic";
  points.views = data.views;
  points.image_width = points.image_height = side;
  return points;
}

const ModelScore* ScoreOf(const ModelSelection& m, LensModel model) {
  for (const ModelScore& s : m.scores) {
    if (s.model == model) return &s;
  }
  return nullptr;
}

// The rule's paired z of a against b over the views both use (calib/model_select.h).
double PairedZ(const ModelScore& a, const ModelScore& b) {
  std::vector<double> d;
  for (size_t i = 0; i < b.used_views.size(); ++i) {
    for (size_t j = 0; j < a.used_views.size(); ++j) {
      if (a.used_views[j] == b.used_views[i]) d.push_back(a.held_out[j] - b.held_out[i]);
    }
  }
  double mean = 0, var = 0;
  for (double x : d) mean += x / d.size();
  for (double x : d) var += (x - mean) * (x - mean) / (d.size() - 1);
  return var > 0 ? mean / std::sqrt(var / d.size()) : 0.0;
}

// A double-sphere fisheye of 190 degrees (TUM VI-like) and a pinhole with radial distortion: the
// pick's held-out error is within noise (z <= 2) of the truth family's, every candidate is in the
// table, and the pick has the fewest parameters of those within noise of the best. Measured
// (printed): the fisheye picks double-sphere itself (eucm 4.0 above it in z, unified 1.93 but 9
// parameters; the radtan models 3.9, pinhole-equi not compared: 8 views past 90 deg left out);
// the pinhole picks eucm (6 parameters, z 1.97 against unified, 1.90 against pinhole-radtan4),
// the double sphere is skipped there (its Jacobian is rank deficient on a 55-degree lens).
// Mutations caught: the pick by the least held-out RMS (the fewest parameters dropped: unified
// picked for the pinhole while pinhole-radtan4 and eucm are within noise); pinhole-equi compared
// on its 12 easier views (it was then the best, and eucm, 4.0 above the truth's family, picked).
TEST(ModelSelect, AutoPicksAModelWithinNoiseOfTheTruthsFamily) {
  CameraIntrinsics ds;
  ds.family = LensFamily::kDoubleSphere;
  ds.fku_px = 0.8 * 300, ds.fkv_px = 0.8 * 300.6, ds.u0_px = 515.3, ds.v0_px = 508.6;
  ds.xi = -0.2, ds.alpha = 0.6;
  const CameraIntrinsics radtan{620, 621.5, 90, 318, 243, -0.28, 0.09, 2e-4, -3e-4, 0.0};
  const struct {
    CameraIntrinsics truth;
    LensModel family_model;
    int side;
  } cases[] = {{ds, LensModel::kDoubleSphere, 1024}, {radtan, LensModel::kPinholeRadTan4, 640}};
  for (const auto& c : cases) {
    Rng rng(77);
    SyntheticBoardViews data;
    if (c.truth.family == LensFamily::kRadTan) {
      SyntheticBoardOptions o;
      o.num_views = 20;
      o.pixel_sigma_px = 0.2;
      o.image_width = o.image_height = c.side;
      data = MakeBoardViews(c.truth, o, &rng);
    } else {
      WideBoardOptions o;
      o.num_views = 20;
      o.max_angle_deg = 95;
      o.pixel_sigma_px = 0.2;
      o.image_width = o.image_height = c.side;
      data = MakeWideBoardViews(c.truth, o, &rng);
    }
    const ModelSelection m = SelectLensModel(Points(data, c.side), {});
    std::cout << FormatModelSelection(m);
    ASSERT_TRUE(m.IsUsable()) << m.reason;
    const ModelScore* truth = ScoreOf(m, c.family_model);
    ASSERT_NE(truth, nullptr);
    ASSERT_TRUE(truth->cross_validated) << truth->note;
    const ModelScore& chosen = m.scores[m.chosen];
    const double z = PairedZ(chosen, *truth);
    std::printf("[ measured ] truth %s, picked %s: z vs the truth's family %.2f\n",
                ToString(c.family_model), ToString(chosen.model), z);
    EXPECT_LE(z, kWithinNoiseZ);
    EXPECT_TRUE(chosen.within_noise);
    for (const ModelScore& s : m.scores) {
      if (s.within_noise) {
        EXPECT_GE(s.free_params, chosen.free_params) << ToString(s.model);
      }
    }
    EXPECT_EQ(m.scores.size(), AutoCandidates().size());
  }
}

}  // namespace
}  // namespace calibench
