// Method `dlt`: the normalised DLT (batch/dlt.h) of a constant M on every frame pooled (points in
// the parent frame, so non-coplanar points are needed). Its estimate: the linear form theta of M
// (theta_z = M's third row) and the decomposed camera. Online mode (window_s, every_s):
// methods/online.h.
#include "batch/dlt.h"

#include "methods/method.h"
#include "methods/online.h"

namespace calibench {
namespace {

class DltMethod final : public Method {
 public:
  std::unique_ptr<Method> Clone() const override { return std::make_unique<DltMethod>(*this); }
  void VisitOptions(OptionVisitor* v) override {
    v->Field({"min_planarity_ratio", "",
              "The pooled points count as coplanar (refused) when the smallest singular value of "
              "their centred scatter is below this fraction of the largest."},
             &options_.min_planarity_ratio);
    online_.Visit(v);
  }
  bool Check(std::string* why) const override { return options_.Check(why) && online_.Check(why); }

  MethodResult Run(const MethodInput& input, EstimateSink* sink) const override {
    MethodResult refused;
    if (RefuseWideLens(input, "dlt", &refused)) return refused;
    return RunMaybeOnline(
        input, online_, sink,
        [this](const MethodInput& window, const CameraEstimate*) { return Solve(window); });
  }

 private:
  MethodResult Solve(const MethodInput& input) const {
    std::vector<Eigen::Vector3d> points;
    std::vector<Eigen::Vector2d> pixels;
    for (const View& v : input.Frames().views) {
      points.insert(points.end(), v.points.begin(), v.points.end());
      pixels.insert(pixels.end(), v.pixels.begin(), v.pixels.end());
    }
    const DltResult dlt = EstimateDlt(points, pixels, options_);
    MethodResult result;
    static_cast<MethodSummary&>(result) = dlt;
    if (!dlt.IsUsable()) return result;
    CameraEstimate& e = result.estimate;
    e.theta = ThetaFromM(dlt.m);
    e.has_camera = true;
    e.intrinsics = dlt.camera.intrinsics;
    e.parent_from_cam = dlt.camera.parent_from_cam;
    e.cam_from_parent = dlt.camera.parent_from_cam.Inverse();
    e.improper = dlt.camera.improper;
    e.orthogonality_defect = dlt.camera.orthogonality_defect;
    return result;
  }

  DltOptions options_;
  OnlineOptions online_;
};

}  // namespace

std::unique_ptr<Method> MakeDltMethod() { return std::make_unique<DltMethod>(); }

}  // namespace calibench
