// SceneRenderer: frame k of a trial, the one definition shared by the rendered measurement source
// (detect/rendered_source.h) and `calibench render`. At t_k the scene places each AprilGrid in the
// camera,
//   cam_from_board(t) = CamFromParent(t) * ParentFromPoints(t) * points_from_board   (scene.h),
// and FrameRenderer (render.h) draws the 8-bit image through the calibration at t (the truth
// changes included) with pixel noise drawn from the stream (trial seed, k) alone, so a frame never
// depends on which thread renders it or in what order.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sim/render.h"
#include "sim/scene.h"
#include "sim/tag_family.h"
#include "sim/target.h"

namespace calibench {

// Keeps references to the scene and the grids, which must outlive it. Render() is const and
// thread-safe.
class SceneRenderer {
 public:
  // nullptr (and *why) for invalid options or a grid family the library does not have.
  static std::unique_ptr<SceneRenderer> Create(const SceneTruth& scene,
                                               const std::vector<AprilGrid>& grids,
                                               const RenderOptions& options, std::string* why);
  // The boards at time t as the renderer takes them (cam_from_board from the scene's motion).
  std::vector<BoardView> ViewsAt(double t) const;
  // Renders frame k (time t); *views receives ViewsAt(t).
  bool Render(double t, uint64_t trial_seed, int k, GrayImage* image, std::vector<BoardView>* views,
              std::string* why) const;

 private:
  SceneRenderer(const SceneTruth& scene, const std::vector<AprilGrid>& grids)
      : scene_(scene), grids_(grids) {}
  const SceneTruth& scene_;
  const std::vector<AprilGrid>& grids_;
  std::vector<std::shared_ptr<const TagFamily>> families_;  // Per grid.
  std::unique_ptr<FrameRenderer> renderer_;
};

}  // namespace calibench
