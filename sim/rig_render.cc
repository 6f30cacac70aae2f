#include "sim/rig_render.h"

#include <cmath>

namespace calibench {

bool RigRenderOptions::Check(std::string* why) const {
  if (!(noise_sigma_gray >= 0) || !std::isfinite(noise_sigma_gray) || !(blur_sigma_px >= 0) ||
      !std::isfinite(blur_sigma_px)) {
    if (why) *why = "noise_sigma_gray and blur_sigma_px must be finite and >= 0";
    return false;
  }
  return true;
}

namespace {

bool CheckRigForRendering(const CameraRig& rig, const RigRenderOptions& options, std::string* why) {
  if (!rig.Check(why) || !options.Check(why)) return false;
  for (int c = 0; c < rig.NumCameras(); ++c) {
    if (rig.cameras[c].image_width <= 0) {
      if (why) *why = "camera " + std::to_string(c) + ": no image size to render";
      return false;
    }
  }
  return true;
}

}  // namespace

std::unique_ptr<RigRenderer> RigRenderer::Create(const CameraRig& rig,
                                                 const CheckerboardPattern& pattern,
                                                 const RigRenderOptions& options,
                                                 std::string* why) {
  if (!CheckRigForRendering(rig, options, why) || !pattern.Check(why)) return nullptr;
  std::unique_ptr<RigRenderer> renderer(new RigRenderer());
  renderer->rig_ = rig;
  renderer->options_ = options;
  renderer->pattern_ = pattern;
  return renderer;
}

std::unique_ptr<RigRenderer> RigRenderer::Create(const CameraRig& rig, const AprilGrid& grid,
                                                 const RigRenderOptions& options,
                                                 std::string* why) {
  if (!CheckRigForRendering(rig, options, why)) return nullptr;
  std::unique_ptr<RigRenderer> renderer(new RigRenderer());
  renderer->rig_ = rig;
  renderer->options_ = options;
  renderer->checkerboard_ = false;
  renderer->grid_ = grid;
  renderer->family_ = TagFamily::Create(grid.family, grid.black_tag_border, why);
  if (!renderer->family_) return nullptr;
  for (const RigCamera& camera : rig.cameras) {
    RenderOptions render;
    render.width = camera.image_width;
    render.height = camera.image_height;
    render.noise_sigma_gray = options.noise_sigma_gray;
    render.blur_sigma_px = options.blur_sigma_px;
    renderer->renderers_.push_back(FrameRenderer::Create(camera.intrinsics, render, why));
    if (!renderer->renderers_.back()) return nullptr;
  }
  return renderer;
}

bool RigRenderer::Render(const Rigid3& rig_from_board, Rng* rng, std::vector<GrayImage>* images,
                         std::string* why) const {
  images->assign(rig_.cameras.size(), GrayImage());
  for (int c = 0; c < rig_.NumCameras(); ++c) {
    const RigCamera& camera = rig_.cameras[c];
    const Rigid3 cam_from_board = camera.cam_from_rig * rig_from_board;
    if (checkerboard_) {
      CheckerboardImageOptions image;
      image.width = camera.image_width;
      image.height = camera.image_height;
      image.noise_sigma_gray = options_.noise_sigma_gray;
      image.blur_sigma_px = options_.blur_sigma_px;
      if (!RenderCheckerboard(camera.intrinsics, cam_from_board, pattern_, image, rng,
                              &(*images)[c], why)) {
        return false;
      }
    } else if (!renderers_[c]->Render({BoardView{grid_, family_, cam_from_board}}, rng,
                                      &(*images)[c], why)) {
      return false;
    }
  }
  return true;
}

}  // namespace calibench
