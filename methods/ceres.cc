// Method `ceres`: maximum likelihood over the intrinsics (its lens model, optional skew) and the
// constant extrinsic (batch/refine.h with one shared pose: the points are already in the parent
// frame through the known body motion), on every frame. It starts from the estimate of its `init`
// (the scenario's instance of that name, or that type's default: dlt or zhang) and reports the
// covariance's standard deviations and the joint covariance of the intrinsics and the extrinsic
// (camera/estimate.h's layout; batch/refine.h EstimateCovarianceOfSharedPose), from which the
// metrics predict its projection uncertainty. Its rows carry the Cramer-Rao bound of its
// parametrisation.
// Online mode (window_s, every_s; methods/online.h): each window's solve starts from the previous
// window's solution (the first from its init on that window).
// `views: init` (the twin of a planar-target calibration): instead of every frame with the rig
// constraint, exactly the views its init used (zhang's, after max_views), with one board pose per
// view and no rig constraint, the extrinsic then by chordal averaging of the per-view poses as
// zhang does; so "less data" and "worse estimator" can be told apart. Its rows carry no CRLB (the
// bound of the rig parametrisation would not be its own).
#include <cmath>

#include "batch/extrinsic_from_views.h"
#include "batch/refine.h"
#include "methods/method.h"
#include "methods/online.h"

namespace calibench {
namespace {

class CeresMethod final : public Method {
 public:
  CeresMethod() {
    options_.shared_pose = true;
    options_.model = LensModel::kPinhole;
    options_.estimate_skew = true;
  }
  std::unique_ptr<Method> Clone() const override { return std::make_unique<CeresMethod>(*this); }

  void VisitOptions(OptionVisitor* v) override {
    v->Field({"init", "",
              "The method it starts from: an instance of the scenario, or a type's default (dlt, "
              "zhang)."},
             &init_, {});
    v->Field({"model", "", "Lens model of the refinement."}, &options_.model);
    v->Field({"estimate_skew", "", "Estimate the skew angle φ; false fixes φ = 90°."},
             &options_.estimate_skew);
    EnumOption(v, {"loss", "", "Robust loss on the reprojection residuals."}, &options_.loss,
               RobustLossNames());
    v->Field({"loss_scale_px", "px", "Scale of the robust loss."}, &options_.loss_scale_px);
    v->Field({"max_iterations", "", "Cap on the Ceres solver's iterations."},
             &options_.max_iterations);
    v->Field({"autodiff", "",
              "Jacobians by ceres::Jet automatic differentiation (the reference) instead of the "
              "analytic ones."},
             &options_.autodiff);
    EnumOption(v,
               {"views", "",
                "frames: every frame, one shared pose; init: exactly the views its init used, one "
                "pose per view (the twin of a planar-target calibration)."},
               &views_, {{Views::kFrames, "frames"}, {Views::kInit, "init"}});
    online_.Visit(v);
  }
  bool Check(std::string* why) const override {
    if (init_.empty()) {
      if (why) *why = "init must name the method it starts from (dlt, zhang or an instance)";
      return false;
    }
    if (views_ == Views::kInit && online_.Online()) {
      if (why) *why = "views: init has no online mode (window_s must be 0)";
      return false;
    }
    return options_.Check(why) && online_.Check(why);
  }
  std::vector<std::string> Prerequisites() const override { return {init_}; }
  std::optional<Parametrisation> BoundParametrisation() const override {
    if (views_ == Views::kInit) return std::nullopt;
    return ParametrisationOf(options_);
  }

  MethodResult Run(const MethodInput& input, EstimateSink* sink) const override {
    return RunMaybeOnline(input, online_, sink,
                          [this](const MethodInput& window, const CameraEstimate* warm) {
                            return Solve(window, warm);
                          });
  }

 private:
  MethodResult Solve(const MethodInput& input, const CameraEstimate* warm) const {
    MethodResult result;
    const CameraEstimate* start = warm;
    if (start == nullptr) {
      const MethodResult& init = input.Prerequisite(init_);
      if (!init.IsUsable() || !init.estimate.has_camera) {
        result.status = MethodStatus::kFailed;
        result.message = "initialisation (" + init_ + ") failed: " + init.message;
        return result;
      }
      start = &init.estimate;
      if (views_ == Views::kInit) return SolveOnInitViews(init);
    }
    RefineOptions options = options_;
    options.compute_pose_covariance = true;  // The estimate's covariance (its projection's).
    options.normal_equations = online_.Online();
    const RefineResult r = RefineCalibration(input.Frames().views, start->intrinsics,
                                             {start->cam_from_parent}, options);
    static_cast<MethodSummary&>(result) = r;
    if (!r.IsUsable()) return result;
    CameraEstimate& e = result.estimate;
    e.has_camera = true;
    e.intrinsics = r.intrinsics;
    e.lens = options_.model;
    e.cam_from_parent = r.cam_from_object[0];
    e.parent_from_cam = r.cam_from_object[0].Inverse();
    e.intrinsics_std = r.intrinsics_std;
    e.covariance = EstimateCovarianceOfSharedPose(r.joint_covariance, e.cam_from_parent);
    e.projection = r.projection;  // With the lens terms the 11 x 11 lacks.
    return result;
  }

  // views: init. The init's per-view problem re-solved by this instance's model, then the
  // extrinsic by chordal averaging of parent_from_board_v * cam_from_board_v^-1.
  MethodResult SolveOnInitViews(const MethodResult& init) const {
    MethodResult result;
    if (init.per_view == nullptr || init.per_view->views.empty()) {
      result.status = MethodStatus::kFailed;
      result.message = "views: init needs an init that solves per-view problems (zhang); " + init_ +
                       " reports none";
      return result;
    }
    const PerViewSolution& pv = *init.per_view;
    RefineOptions options = options_;
    options.shared_pose = false;
    const RefineResult r =
        RefineCalibration(pv.views, init.estimate.intrinsics, pv.cam_from_board, options);
    static_cast<MethodSummary&>(result) = r;
    result.frames_used = init.frames_used;
    result.observations_used = init.observations_used;
    if (!r.IsUsable()) return result;
    std::vector<Rigid3> parent_from_cam_views;
    for (size_t v = 0; v < pv.views.size(); ++v)
      parent_from_cam_views.push_back(pv.parent_from_board[v] * r.cam_from_object[v].Inverse());
    CameraEstimate& e = result.estimate;
    e.has_camera = true;
    e.intrinsics = r.intrinsics;
    e.lens = options_.model;
    e.parent_from_cam = AveragePoses(parent_from_cam_views);
    e.cam_from_parent = e.parent_from_cam.Inverse();
    e.intrinsics_std = r.intrinsics_std;
    e.fit_rms_px = r.rms_reproj_px;  // One pose per view, as zhang's figure.
    return result;
  }

  std::string init_ = "dlt";
  // kFrames: every frame, one shared pose; kInit: the views its init used, a pose per view.
  enum class Views { kFrames, kInit };
  Views views_ = Views::kFrames;
  RefineOptions options_;
  OnlineOptions online_;
};

}  // namespace

std::unique_ptr<Method> MakeCeresMethod() { return std::make_unique<CeresMethod>(); }

}  // namespace calibench
