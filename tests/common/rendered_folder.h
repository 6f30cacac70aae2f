// Test fixture data on disk: a folder of PNG views of an AprilGrid or a checkerboard rendered by a
// known camera (calibrate --images input with a known answer). Poses come from sim/synthetic.h.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "sim/checkerboard_image.h"
#include "sim/render.h"
#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {

struct RenderedFolderOptions {
  int views = 12;
  double noise_sigma_gray = 1.0;
  uint64_t seed = 2024;
  double lateral_m = 0.05;  // Board centres spread over +-lateral_m in x, +-0.8 lateral_m in y.
  double min_distance_m = 0.45, max_distance_m = 0.6;  // Of the board centre.
  int width = 640, height = 480;
  double blur_sigma_px = 0.0;
};

// A random facing viewpoint (tilt up to ~35 degrees, min_distance_m..max_distance_m) of the board
// point `centre`.
inline Rigid3 RandomFacingView(const RenderedFolderOptions& options, const Eigen::Vector3d& centre,
                               Rng* rng) {
  // Each vector's entries drawn last first (util/random.h).
  const double tilt_z = rng->Uniform(-0.4, 0.4), tilt_y = rng->Uniform(-0.6, 0.6);
  const Eigen::Vector3d tilt(rng->Uniform(-0.6, 0.6), tilt_y, tilt_z);
  const double distance = rng->Uniform(options.min_distance_m, options.max_distance_m);
  const double lateral = options.lateral_m;
  const double at_y = rng->Uniform(-0.8 * lateral, 0.8 * lateral);
  const Eigen::Vector3d at(rng->Uniform(-lateral, lateral), at_y, distance);
  // ExpSO3(tilt) D = D ExpSO3(D tilt) for D = diag(1, -1, -1).
  return FacingBoardPose({tilt.x(), -tilt.y(), -tilt.z()}, centre, at);
}

// True when every point projects more than `margin` px inside the image.
inline bool AllInside(const CameraIntrinsics& truth, const Rigid3& cam_from_board,
                      const std::vector<Eigen::Vector3d>& points, const RenderedFolderOptions& o,
                      double margin) {
  for (const Eigen::Vector3d& p : points) {
    Eigen::Vector2d pixel;
    if (!ProjectPoint(truth, cam_from_board * p, &pixel) || pixel.x() < margin ||
        pixel.y() < margin || pixel.x() > o.width - 1 - margin ||
        pixel.y() > o.height - 1 - margin) {
      return false;
    }
  }
  return true;
}

inline bool WritePng(const std::string& path, GrayImage* image) {
  const cv::Mat mat(image->height, image->width, CV_8UC1, image->pixels.data());
  return cv::imwrite(path, mat);
}

// Writes DIR/view<k>.png (k < options.views) of `grid` seen by `truth` from random facing
// viewpoints (RandomFacingView, every corner > 5 px inside the image).
// Returns the number of views written (< options.views only if poses ran out).
inline int WriteRenderedAprilGridFolder(const std::string& dir, const CameraIntrinsics& truth,
                                        const AprilGrid& grid,
                                        const RenderedFolderOptions& options) {
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto family = TagFamily::Create(grid.family, grid.black_tag_border, nullptr);
  RenderOptions render_options;
  render_options.noise_sigma_gray = options.noise_sigma_gray;
  render_options.width = options.width;
  render_options.height = options.height;
  render_options.blur_sigma_px = options.blur_sigma_px;
  const auto renderer = FrameRenderer::Create(truth, render_options, nullptr);
  if (!family || !renderer) return 0;
  const double extent = grid.tag_cols * grid.Pitch() - grid.Pitch() + grid.tag_size_m;
  const Eigen::Vector3d centre(extent / 2, extent / 2, 0);
  Rng rng(options.seed);
  int written = 0;
  for (int attempt = 0; written < options.views && attempt < 200; ++attempt) {
    BoardView view{grid, family, RandomFacingView(options, centre, &rng)};
    if (!AllInside(truth, view.cam_from_board, grid.CornersInBoard(), options, 5)) continue;
    GrayImage image;
    if (!renderer->Render({view}, &rng, &image, nullptr)) return written;
    if (!WritePng(dir + "/view" + std::to_string(written) + ".png", &image)) return written;
    ++written;
  }
  return written;
}

// The same for a checkerboard (sim/checkerboard_image.h): every inner corner and the outer squares'
// corners (one square beyond) > 5 px inside the image.
inline int WriteRenderedCheckerboardFolder(const std::string& dir, const CameraIntrinsics& truth,
                                           const CheckerboardPattern& pattern,
                                           const RenderedFolderOptions& options) {
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  CheckerboardImageOptions image_options;
  image_options.width = options.width;
  image_options.height = options.height;
  image_options.blur_sigma_px = options.blur_sigma_px;
  image_options.noise_sigma_gray = options.noise_sigma_gray;
  std::vector<Eigen::Vector3d> outline;  // The squares' outer corners.
  for (int r = -1; r <= pattern.rows; ++r) {
    for (int c = -1; c <= pattern.cols; ++c) outline.push_back(pattern.Corner(r, c));
  }
  const Eigen::Vector3d centre =
      pattern.Corner(0, 0) / 2 + pattern.Corner(pattern.rows - 1, pattern.cols - 1) / 2;
  Rng rng(options.seed);
  int written = 0;
  for (int attempt = 0; written < options.views && attempt < 200; ++attempt) {
    const Rigid3 cam_from_board = RandomFacingView(options, centre, &rng);
    if (!AllInside(truth, cam_from_board, outline, options, 5)) continue;
    GrayImage image;
    if (!RenderCheckerboard(truth, cam_from_board, pattern, image_options, &rng, &image, nullptr) ||
        !WritePng(dir + "/view" + std::to_string(written) + ".png", &image)) {
      return written;
    }
    ++written;
  }
  return written;
}

}  // namespace calibench
