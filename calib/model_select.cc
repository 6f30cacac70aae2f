#include "calib/model_select.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace calibench {
namespace {

int FreeParams(LensModel model, bool estimate_skew) {
  return PinholeSkewCamera::kNumParams -
         static_cast<int>(FixedIntrinsics(model, estimate_skew).size());
}

ModelScore FitCandidate(const PointData& data, LensModel model, bool estimate_skew) {
  ModelScore s;
  s.model = model;
  s.free_params = FreeParams(model, estimate_skew);
  CalibrateOptions options;
  options.model = model;
  options.estimate_skew = estimate_skew;
  s.report = CalibrateFromPoints(data, options);
  s.fitted = s.report.IsUsable();
  if (!s.fitted) {
    s.note = s.report.ceres.message;
    return s;
  }
  s.used_views = s.report.zhang.used_views;
  s.views = static_cast<int>(s.used_views.size());
  s.rms_px = s.report.ceres.rms_reproj_px;
  if (s.views < static_cast<int>(data.views.size())) {
    s.note = std::to_string(data.views.size() - s.used_views.size()) + " view(s) left out";
  }
  return s;
}

// The held-out errors e_v of the header comment; false (with the reason in s->note) when a
// training fit fails.
bool CrossValidate(const PointData& data, int folds, bool estimate_skew, ModelScore* s) {
  const int k = std::min(folds, s->views);
  s->held_out.assign(s->used_views.size(), 0.0);
  double sum = 0;
  long points = 0;
  for (int fold = 0; fold < k; ++fold) {
    std::vector<View> train, test;
    std::vector<Rigid3> train_poses, test_poses;
    std::vector<size_t> test_at;
    for (size_t i = 0; i < s->used_views.size(); ++i) {
      const int v = s->used_views[i];
      const bool held = v % k == fold;
      (held ? test : train).push_back(data.views[v]);
      (held ? test_poses : train_poses).push_back(s->report.ceres.cam_from_object[i]);
      if (held) test_at.push_back(i);
    }
    if (test.empty()) continue;
    RefineOptions refine;
    refine.model = s->model;
    refine.estimate_skew = estimate_skew;
    refine.compute_covariance = false;
    const RefineResult fit =
        RefineCalibration(train, s->report.ceres.intrinsics, train_poses, refine);
    refine.fix_intrinsics = true;
    const RefineResult held =
        fit.IsUsable() ? RefineCalibration(test, fit.intrinsics, test_poses, refine) : fit;
    if (!held.IsUsable()) {
      s->note = "cross-validation fold " + std::to_string(fold) + ": " + held.message;
      return false;
    }
    for (size_t j = 0; j < test.size(); ++j) {
      const double n = static_cast<double>(test[j].points.size());
      s->held_out[test_at[j]] = held.view_rms_px[j] * held.view_rms_px[j] * n;
      sum += s->held_out[test_at[j]];
      points += static_cast<long>(n);
    }
  }
  s->cv_rms_px = std::sqrt(sum / std::max(1L, points));
  s->held_out_points = points;
  return true;
}

// The rule's z of `s` against `best` over the views both use; +inf when s leaves out a view the
// best uses.
double PairedZ(const ModelScore& s, const ModelScore& best) {
  std::vector<double> d;
  for (size_t b = 0; b < best.used_views.size(); ++b) {
    const auto it = std::find(s.used_views.begin(), s.used_views.end(), best.used_views[b]);
    if (it == s.used_views.end()) return std::numeric_limits<double>::infinity();
    d.push_back(s.held_out[it - s.used_views.begin()] - best.held_out[b]);
  }
  const double n = static_cast<double>(d.size());
  double mean = 0, var = 0;
  for (double x : d) mean += x / n;
  for (double x : d) var += (x - mean) * (x - mean) / std::max(1.0, n - 1);
  if (var == 0)
    return mean == 0 ? 0.0 : std::copysign(std::numeric_limits<double>::infinity(), mean);
  return mean / std::sqrt(var / n);
}

// proj_diff_* of the header comment.
void ProjectionDifference(const PointData& data, const CameraIntrinsics& best,
                          const CameraIntrinsics& other, ModelScore* s) {
  const Eigen::Vector2d centre(best.u0_px, best.v0_px);
  double reach = 0;
  for (const View& v : data.views) {
    for (const Eigen::Vector2d& p : v.pixels) reach = std::max(reach, (p - centre).norm());
  }
  double sum_sq = 0, worst = 0;
  long count = 0;
  for (int y = 0; y < data.image_height; y += kDiffGridStep) {
    for (int x = 0; x < data.image_width; x += kDiffGridStep) {
      const Eigen::Vector2d pixel(x, y);
      Eigen::Vector3d ray;
      Eigen::Vector2d q;
      if ((pixel - centre).norm() > reach || !UnprojectToRay(best, pixel, &ray)) continue;
      if (!ProjectPoint(other, ray, &q)) continue;  // Outside the candidate's region.
      const double d = (q - pixel).norm();
      sum_sq += d * d;
      worst = std::max(worst, d);
      ++count;
    }
  }
  s->proj_diff_rms_px = count > 0 ? std::sqrt(sum_sq / count) : 0.0;
  s->proj_diff_max_px = worst;
}

std::string PickReason(const ModelSelection& m) {
  const ModelScore &c = m.scores[m.chosen], &b = m.scores[m.best];
  char text[400];
  if (m.chosen == m.best) {
    std::snprintf(text, sizeof(text),
                  "%s has the least held-out RMS (%.4f px) and no model with fewer parameters is "
                  "within noise of it",
                  ToString(c.model), c.cv_rms_px);
  } else {
    std::snprintf(text, sizeof(text),
                  "%s (%d parameters) is within noise of the best, %s (%d parameters, held-out "
                  "RMS %.4f px): held-out RMS %.4f px, z = %.2f <= %.0f, and it has the fewest "
                  "parameters of those within noise",
                  ToString(c.model), c.free_params, ToString(b.model), b.free_params, b.cv_rms_px,
                  c.cv_rms_px, c.z_vs_best, kWithinNoiseZ);
  }
  return text;
}

// A number of the table, or ">1e4" past it (a model that cannot follow the best one there).
std::string Shown(double value, const char* format) {
  if (!(std::abs(value) < 1e4)) return value > 0 ? ">1e4" : "<-1e4";
  char text[32];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

}  // namespace

const std::vector<LensModel>& AutoCandidates() {
  // pinhole-radtan4, then every family's full model (camera/lens_families.h).
  static const std::vector<LensModel> candidates = [] {
    std::vector<LensModel> models = {LensModel::kPinholeRadTan4};
    for (const LensFamilyInfo& info : LensFamilies()) models.push_back(FullModelOf(info.family));
    return models;
  }();
  return candidates;
}

bool ModelSelectOptions::Check(std::string* why) const {
  std::string msg;
  if (candidates.empty()) msg = "no candidate lens model";
  if (folds < 2) msg = "folds must be >= 2";
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

ModelSelection SelectLensModel(const PointData& data, const ModelSelectOptions& options) {
  ModelSelection m;
  std::string why;
  if (!options.Check(&why)) {
    m.reason = "model selection: " + why;
    return m;
  }
  int most_views = 0;
  for (LensModel model : options.candidates) {
    ModelScore s = FitCandidate(data, model, options.estimate_skew);
    if (s.fitted && s.views >= 2) {
      s.cross_validated = CrossValidate(data, options.folds, options.estimate_skew, &s);
    }
    if (s.cross_validated) most_views = std::max(most_views, s.views);
    m.scores.push_back(std::move(s));
  }
  // Held-out errors compare over the same views: a model that leaves views out (pinhole-equi past
  // 90 degrees) is listed, not compared.
  for (size_t i = 0; i < m.scores.size(); ++i) {
    ModelScore& s = m.scores[i];
    s.comparable = s.cross_validated && s.views == most_views;
    if (s.cross_validated && !s.comparable) s.note += ": not compared (fewer views)";
    if (s.comparable && (m.best < 0 || s.cv_rms_px < m.scores[m.best].cv_rms_px)) {
      m.best = static_cast<int>(i);
    }
  }
  if (m.best < 0) {
    m.reason = "no candidate lens model could be fitted and cross-validated";
    return m;
  }
  const ModelScore& best = m.scores[m.best];
  for (size_t i = 0; i < m.scores.size(); ++i) {
    ModelScore& s = m.scores[i];
    if (!s.cross_validated) continue;
    s.z_vs_best = static_cast<int>(i) == m.best ? 0.0 : PairedZ(s, best);
    const double rms_noise =
        kRmsNoiseSigmas / std::sqrt(2.0 * 2.0 * static_cast<double>(best.held_out_points));
    s.within_noise = s.comparable && s.z_vs_best <= kWithinNoiseZ &&
                     s.cv_rms_px <= best.cv_rms_px * (1 + rms_noise);
    ProjectionDifference(data, best.report.ceres.intrinsics, s.report.ceres.intrinsics, &s);
    if (s.within_noise && (m.chosen < 0 || s.free_params < m.scores[m.chosen].free_params)) {
      m.chosen = static_cast<int>(i);
    }
  }
  m.reason = PickReason(m);
  return m;
}

std::string FormatModelSelection(const ModelSelection& m) {
  std::ostringstream out;
  char line[300];
  out << "model selection (--model auto): every candidate fitted, then leave-k-views-out\n"
      << "model            params views  rms_px    cv_rms_px  z_vs_best  diff_rms_px  diff_max_px"
         "  note\n";
  for (size_t i = 0; i < m.scores.size(); ++i) {
    const ModelScore& s = m.scores[i];
    if (!s.cross_validated) {
      std::snprintf(line, sizeof(line), "%-16s %6d %5s  %-8s  %-9s  %-9s  %-11s  %-11s  %s\n",
                    ToString(s.model), s.free_params, "-", "-", "-", "-", "-", "-",
                    ("skipped: " + s.note).c_str());
    } else {
      std::string note = s.note;
      auto prefix = [&note](const char* label) {
        std::string labelled = label;
        if (!note.empty()) labelled.append("; ").append(note);
        note = labelled;
      };
      if (static_cast<int>(i) == m.best) prefix("best held-out");
      if (static_cast<int>(i) == m.chosen) prefix("CHOSEN");
      std::snprintf(line, sizeof(line), "%-16s %6d %5d  %-8.4f  %-9.4f  %-9s  %-11s  %-11s  %s\n",
                    ToString(s.model), s.free_params, s.views, s.rms_px, s.cv_rms_px,
                    s.comparable ? Shown(s.z_vs_best, "%.2f").c_str() : "-",
                    Shown(s.proj_diff_rms_px, "%.4f").c_str(),
                    Shown(s.proj_diff_max_px, "%.4f").c_str(), note.c_str());
    }
    out << line;
  }
  std::snprintf(line, sizeof(line),
                "rule: the fewest parameters among the models within noise of the best held-out "
                "RMS: paired z over views <= %.0f and held-out RMS <= best x (1 + %.0f / "
                "sqrt(2 m)), m held-out residuals (%.0f std of an RMS); models that leave views "
                "out are not compared\n",
                kWithinNoiseZ, kRmsNoiseSigmas, kRmsNoiseSigmas);
  out << line;
  out << (m.IsUsable() ? "picked: " : "no pick: ") << m.reason << "\n";
  return out.str();
}

}  // namespace calibench
