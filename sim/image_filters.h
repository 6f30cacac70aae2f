// The image-space steps of rendering a frame (sim/render.h), on a float image stored row-major,
// width x height, gray levels:
//   the optics' PSF:      BlurNearBoards / GaussianBlur (a separable Gaussian, edges clamped);
//   pixel integration:    SumBlocks (the mean of each m x m block of a finer grid), or with the
//                         blur in one pass, BlurNearBoardsAndSumBlocks;
//   the sensor's noise:   AddImageNoise (iid N(0, sigma^2) per pixel, from a shared table).
// Rounding to 8 bits is render.cc's last step.
#pragma once

#include <array>
#include <vector>

#include "util/random.h"

namespace calibench {

// A pixel box [x0, x1) x [y0, y1).
struct PixelBox {
  int x0, x1, y0, y1;
};

// Adds N(0, sigma^2) to every pixel; the draws depend only on `rng`'s state (render.cc draws it
// from (trial seed, frame)).
void AddImageNoise(double sigma, int width, int height, Rng* rng, std::vector<float>* values);

// Blurs the pixels of `box` (clamped to the image) with a Gaussian of `sigma` px. Exact for the
// whole image when everything outside the box is farther than the kernel's radius (3 sigma) from
// anything but one constant gray, which keeps its value under the blur.
void GaussianBlur(double sigma, int width, int height, const PixelBox& box,
                  std::vector<float>* image);

// GaussianBlur of the boards' box (x0, x1, y0, y1, inclusive; x0 > x1: no board in view) grown
// by the kernel's reach: the background elsewhere is one gray.
void BlurNearBoards(double sigma, int width, int height, const std::array<int, 4>& box,
                    std::vector<float>* image);

// SumBlocks of `fine` after BlurNearBoards(sigma, width m, height m, box) (sigma and box in
// sub-pixels), without storing the blurred sub-pixels: each axis is one pass of the kernel both
// apply, (Gaussian * m-box) / m, evaluated at the pixels' columns (on every sub-pixel row: m (2 r +
// m) products a pixel, r = ceil(3 sigma)), then at their rows (2 r + m), instead of m^2 (2 r + 1)
// a pixel for each axis of the blur. Equal to the two steps to float rounding
// (tests/sim/image_filters_test.cc).
void BlurNearBoardsAndSumBlocks(double sigma, int width, int height, int m,
                                const std::array<int, 4>& box, const std::vector<float>& fine,
                                std::vector<float>* pixels);

// *pixels = the mean of each m x m block of `fine`, a (width m) x (height m) image; the pixels of
// `skip` (when given) are left as they are.
void SumBlocks(const std::vector<float>& fine, int width, int height, int m,
               std::vector<float>* pixels, const PixelBox* skip = nullptr);

}  // namespace calibench
