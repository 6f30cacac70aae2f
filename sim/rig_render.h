// A rig's synchronised frames as images (camera/rig.h): every camera renders the same target at the
// same instant through its own lens and image size, as a real rig's cameras all take an image
// whether or not they see the target. The target is a checkerboard (sim/checkerboard_image.h) or an
// AprilGrid (sim/render.h); camera c sees it from cam_from_rig_c * rig_from_board.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "camera/rig.h"
#include "sim/checkerboard_image.h"
#include "sim/render.h"

namespace calibench {

struct RigRenderOptions {
  double noise_sigma_gray = 1.0;  // Gaussian noise before quantisation.
  double blur_sigma_px = 0.0;     // Gaussian PSF; 0: none.
  bool Check(std::string* why) const;
};

// Renders frames of a rig; holds one AprilGrid renderer per camera (its ray table).
class RigRenderer {
 public:
  // A checkerboard target; nullptr (and *why) for an invalid rig, pattern or options. Every camera
  // needs an image size.
  static std::unique_ptr<RigRenderer> Create(const CameraRig& rig,
                                             const CheckerboardPattern& pattern,
                                             const RigRenderOptions& options, std::string* why);
  // An AprilGrid target.
  static std::unique_ptr<RigRenderer> Create(const CameraRig& rig, const AprilGrid& grid,
                                             const RigRenderOptions& options, std::string* why);
  // One image per camera of the target at rig_from_board. The noise is drawn from `rng` in camera
  // order. False (and *why) when a renderer fails.
  bool Render(const Rigid3& rig_from_board, Rng* rng, std::vector<GrayImage>* images,
              std::string* why) const;

 private:
  RigRenderer() = default;
  CameraRig rig_;
  RigRenderOptions options_;
  bool checkerboard_ = true;
  CheckerboardPattern pattern_;
  AprilGrid grid_;
  std::shared_ptr<const TagFamily> family_;
  std::vector<std::unique_ptr<FrameRenderer>> renderers_;  // AprilGrid: one per camera.
};

}  // namespace calibench
