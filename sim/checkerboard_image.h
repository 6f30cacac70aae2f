// Checkerboard images as a camera sees them, through any lens family of camera/camera.h: the input
// of checkerboard corner studies and of calibrate --images tests with a known answer.
//
// The board (CheckerboardPattern): cols x rows inner corners, inner corner (r, c) at
// (c * square_m, r * square_m, 0) in the board frame (the target YAML's convention,
// calib/image_points.cc). Its (cols + 1) x (rows + 1) squares cover
// [-square_m, cols * square_m] x [-square_m, rows * square_m]; square (i, j) (i, j >= -1, the
// square whose lower corner is (i s, j s)) is black when i + j is even, so the square at the
// board origin's upper right is black. A white margin of one square surrounds them; beyond it is
// the background.
//
// A pixel (pixel-centre convention of camera.h) is the mean shade over its area: a pixel whose four
// corners see the same square (or the same margin, or background) is that shade (squares are
// larger than a pixel, so no edge or corner can then cross it); any other pixel is the mean of
// supersample x supersample samples on a sheared grid (distinct x and y offsets: an edge resolved
// to 1 / supersample^2 px; the errors of a pixel's share are independent along an edge), each
// unprojected exactly (UnprojectToRay) and intersected with the board. Blur (a Gaussian PSF) is the
// physical one, as in sim/render.h: the board is shaded on a grid m = ceil(3 / sigma) times finer
// (at most 8), blurred there and summed into pixels. Then Gaussian noise in gray levels
// (AddImageNoise, from `noise_rng`) and rounding to 8 bits.
#pragma once

#include <Eigen/Core>
#include <string>

#include "camera/camera.h"
#include "camera/pose.h"
#include "sim/render.h"

namespace calibench {

struct CheckerboardPattern {
  int cols = 9, rows = 6;  // Inner corners per row and per column.
  double square_m = 0.03;  // Side of a square.
  // Inner corner (r, c) in the board frame.
  Eigen::Vector3d Corner(int r, int c) const { return {c * square_m, r * square_m, 0.0}; }
  // At least 2 x 2 inner corners, at most kMaxCornersPerSide (target.h) a side; a positive,
  // finite square.
  bool Check(std::string* why) const;
};

struct CheckerboardImageOptions {
  int width = 640, height = 480;
  // n x n samples in a pixel that an edge or outline crosses (max(2, ceil(n / m)) in each of the
  // m x m sub-pixels of a blurred frame).
  int supersample = 8;
  double blur_sigma_px = 0.0;     // Gaussian PSF; 0: none.
  double noise_sigma_gray = 0.0;  // Gaussian noise added before quantisation.
  double background_gray = 128.0;
  double black_gray = 25.0;
  double white_gray = 230.0;
  bool Check(std::string* why) const;
};

// Renders the board seen by `camera` from `cam_from_board`; `noise_rng` may be null when
// noise_sigma_gray = 0. False (and *why) for invalid options or pattern.
bool RenderCheckerboard(const CameraIntrinsics& camera, const Rigid3& cam_from_board,
                        const CheckerboardPattern& pattern, const CheckerboardImageOptions& options,
                        Rng* noise_rng, GrayImage* image, std::string* why);

}  // namespace calibench
