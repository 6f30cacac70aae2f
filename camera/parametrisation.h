// Parametrisation: what a calibration estimates, as far as its Cramer-Rao bound is concerned
// (metrics/metrics.h CramerRaoStd): the lens model (which parameters are free), whether the skew
// angle phi is free, and whether the frames share one pose (a rig whose points are known in the
// parent frame) or each view has its own. A method states it (methods/method.h
// BoundParametrisation) without exposing its solver's options.
#pragma once

#include "camera/camera.h"

namespace calibench {

struct Parametrisation {
  LensModel model = LensModel::kPinhole;
  bool estimate_skew = true;  // False: phi fixed at 90 degrees.
  bool shared_pose = false;   // One cam_from_points for every frame, else one pose per view.
  bool autodiff = false;      // Jacobians by ceres::Jet (the reference) instead of analytic ones.
};

}  // namespace calibench
