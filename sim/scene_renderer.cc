#include "sim/scene_renderer.h"

#include "util/random.h"

namespace calibench {

std::unique_ptr<SceneRenderer> SceneRenderer::Create(const SceneTruth& scene,
                                                     const std::vector<AprilGrid>& grids,
                                                     const RenderOptions& options,
                                                     std::string* why) {
  std::unique_ptr<SceneRenderer> r(new SceneRenderer(scene, grids));
  for (const AprilGrid& g : grids) {
    r->families_.push_back(TagFamily::Create(g.family, g.black_tag_border, why));
    if (!r->families_.back()) return nullptr;
  }
  r->renderer_ = FrameRenderer::Create(scene.intrinsics, options, why);
  if (!r->renderer_) return nullptr;
  return r;
}

std::vector<BoardView> SceneRenderer::ViewsAt(double t) const {
  const Rigid3 cam_from_points = scene_.CamFromParentAt(t) * scene_.ParentFromPoints(t);
  std::vector<BoardView> views(grids_.size());
  for (size_t g = 0; g < grids_.size(); ++g) {
    views[g].grid = grids_[g];
    views[g].family = families_[g];
    views[g].cam_from_board = cam_from_points * grids_[g].points_from_board;
  }
  return views;
}

bool SceneRenderer::Render(double t, uint64_t trial_seed, int k, GrayImage* image,
                           std::vector<BoardView>* views, std::string* why) const {
  *views = ViewsAt(t);
  Rng noise(TrialSeed(trial_seed, static_cast<uint64_t>(k)), RngStream::kPixelNoise);
  if (!scene_.HasChanges()) return renderer_->Render(*views, &noise, image, why);
  const CameraIntrinsics intrinsics = scene_.IntrinsicsAt(t);  // The calibration at frame time.
  return renderer_->Render(*views, &noise, image, why, &intrinsics);
}

}  // namespace calibench
