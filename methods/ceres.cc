// Method `ceres`: maximum likelihood over the intrinsics (its lens model, optional skew) and the
// constant extrinsic (batch/refine.h with one shared pose: the points are already in the parent
// frame through the known body motion), on every frame. It starts from the estimate of its `init`
// (the scenario's instance of that name, or that type's default: dlt or zhang) and reports the
// covariance's standard deviations. Its rows carry the Cramer-Rao bound of its parametrisation.
#include <cmath>

#include "batch/refine.h"
#include "methods/method.h"

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
    v->Field("init", &init_, {});
    v->Field("model", &options_.model);
    v->Field("estimate_skew", &options_.estimate_skew);
    v->Field("loss", &options_.loss, {"none", "huber", "cauchy"});
    v->Field("loss_scale_px", &options_.loss_scale_px);
    v->Field("max_iterations", &options_.max_iterations);
    v->Field("autodiff", &options_.autodiff);
  }
  bool Check(std::string* why) const override {
    if (init_.empty()) {
      if (why) *why = "init must name the method it starts from (dlt, zhang or an instance)";
      return false;
    }
    return options_.Check(why);
  }
  std::vector<std::string> Prerequisites() const override { return {init_}; }
  std::optional<RefineOptions> BoundParametrisation() const override { return options_; }

  MethodResult Run(const MethodInput& input, EstimateSink*) const override {
    MethodResult result;
    const MethodResult& init = input.prerequisite(init_);
    if (!init.IsUsable() || !init.estimate.has_camera) {
      result.status = MethodStatus::kFailed;
      result.message = "initialisation (" + init_ + ") failed: " + init.message;
      return result;
    }
    const CameraEstimate& start = init.estimate;
    const RefineResult r = RefineCalibration(input.Frames().views, start.intrinsics,
                                             {start.parent_from_cam.Inverse()}, options_);
    static_cast<MethodSummary&>(result) = r;
    if (!r.IsUsable()) return result;
    CameraEstimate& e = result.estimate;
    e.has_camera = true;
    e.intrinsics = r.intrinsics;
    e.lens = options_.model;
    e.cam_from_parent = r.cam_from_object[0];
    e.parent_from_cam = r.cam_from_object[0].Inverse();
    e.intrinsics_std = r.intrinsics_std;
    return result;
  }

 private:
  std::string init_ = "dlt";
  RefineOptions options_;
};

}  // namespace

std::unique_ptr<Method> MakeCeresMethod() { return std::make_unique<CeresMethod>(); }

}  // namespace calibench
