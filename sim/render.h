// Ray-cast rendering of AprilTag grids as a camera sees them: 8-bit grayscale frames, through
// every lens family of camera/camera.h, past 90 degrees from the axis for the omnidirectional ones.
//
// For every sample point (u, v) of the image (pixel-centre convention of camera.h: pixel (i, j)
// covers [i - 0.5, i + 0.5] x [j - 0.5, j + 0.5]):
//   1. its ray r, any positive multiple of the unit ray of the points that project there
//      (UnprojectToRay; radtan and equidistant: A^-1, then the distortion undone by iteration,
//      r = (x, y, 1)). A point outside the lens's valid region (outside an omnidirectional lens's
//      image circle) has no ray: it sees the background;
//   2. intersect r with every board plane: with cam_from_board = [R | t], the board point
//      b = (bx, by) seen along r satisfies lambda r = [r1 r2 t] (bx, by, 1), lambda > 0, so
//      h = [r1 r2 t]^-1 r gives b = h.xy / h.z at lambda = 1 / h.z: in front iff h.z > 0, for
//      rays with z <= 0 too (r is never flipped to z = 1); keep the nearest hit (smallest lambda)
//      that lands on a board (tags, their white margins, a white frame of one gap around);
//   3. shade: black or white cell of the tag bitmap (TagFamily), white board, or background.
// Antialiasing: a pixel is the mean shade over its area. A pixel whose four corners see the same
// shade of the same board, with no pattern corner (a tag's or a cell's) between them, is that
// shade (features are assumed larger than a pixel: tag cells of a few pixels). A pixel that sees
// one board holds the exact area share of each cell its footprint overlaps: the footprint, the
// quadrilateral of its corners' board points, cut along the cell lines, each piece's area taken in
// the pixel through the homography of its four corners (exact for a pinhole camera; through a
// lens, to second order in the pixel's size). Other pixels (two boards, a board's outline, cells
// far below a pixel) are the mean of n x n traced samples (supersample = n; a sheared grid whose
// n^2 samples have distinct x and y offsets: an axis-aligned edge resolved to 1/n^2 px, not 1/n).
// Then optional Gaussian blur (PSF sigma in px; computed only near the boards: the uniform
// background is unchanged by it), Gaussian noise in gray levels (iid within a frame, read from a
// fixed table of normals in blocks the frame's rng chooses: image_filters.h AddImageNoise), and
// rounding to 8 bits.
// The blur is the physical one: the scene convolved with the PSF, then integrated over each pixel
// (box * Gaussian, the model the photometric fit assumes). A Gaussian applied to the pixels'
// values instead samples the kernel at whole pixels and moves edges with their sub-pixel phase
// (by up to 0.029 px at sigma = 0.5 px, 0.008 px at 1 px). So the frame is rendered on a grid
// m times finer (m x m sub-pixels a pixel, each antialiased as above), blurred there by sigma m
// sub-pixels and summed back into pixels: the edge shift falls to < 5e-4 px for m >= 3 / sigma
// (measured on straight edges; RenderOptions::blur_grid). m = 1 is the fast pixel-level blur.
// Speed: with distortion, FrameRenderer computes the rays of the (w + 1) x (h + 1) pixel corners
// once per camera (without, a corner's ray is A^-1 times the corner); the table holds each in two
// numbers: (x, y) on the plane z = 1 for radtan (rays in front only), the stereographic
// coordinates (X, Y) / (|P| + Z) of the unit ray for the equidistant and omnidirectional families
// (every ray but the backward axis, which no family images; smooth through 90 deg from the axis,
// where the plane's tan(theta) is not: board_shader.h RaySpace). The rays of the samples inside a
// pixel are interpolated bilinearly between its four corners' coordinates (exact without
// distortion; with |k1| <= 0.3 the error is below 1e-3 px), unless a corner has no ray: then each
// sample is unprojected. The finer grid's corners (blur_grid m > 1) are interpolated by the cubic
// through the 4 x 4 nearest pixel corners, not bilinearly: in a 160 deg fisheye's periphery
// bilinear corners moved the blurred edges inwards by 1e-3 px at 60 deg to 7e-3 px at 85 deg off
// the axis (against a reference rendered by point samples through the exact lens), and biased a
// calibration's distortion terms by up to 4 std. With the cubic the edges lie within 1e-4 px of
// the reference there (tests/sim/render_fine_grid_test.cc); what remains is each sub-pixel's
// straight-sided footprint (second order in its size). Without a finer grid (no blur, or
// blur_grid 1) the pixels' own footprints are straight-sided: 3e-4 to 5e-4 px inwards at 40 to
// 80 deg in that fisheye.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/pose.h"
#include "sim/tag_family.h"
#include "sim/target.h"
#include "util/random.h"

namespace calibench {

struct GrayImage {
  int width = 0, height = 0;
  std::vector<uint8_t> pixels;  // Row-major, stride = width.
  uint8_t at(int col, int row) const { return pixels[static_cast<size_t>(row) * width + col]; }
};

// A read-only view of 8-bit gray pixels owned elsewhere (a GrayImage, a cv::Mat): no copy.
struct GrayImageView {
  const uint8_t* data = nullptr;
  int width = 0, height = 0;
  int stride = 0;  // Bytes per row.
  GrayImageView() = default;
  GrayImageView(const uint8_t* d, int w, int h, int s) : data(d), width(w), height(h), stride(s) {}
  GrayImageView(const GrayImage& image)  // NOLINT(google-explicit-constructor): a view of it.
      : data(image.pixels.data()), width(image.width), height(image.height), stride(image.width) {}
  uint8_t at(int col, int row) const { return data[static_cast<size_t>(row) * stride + col]; }
};

// The largest image the renderer accepts (its ray table: 16 bytes per pixel corner, 1 GiB here).
constexpr int kMaxRenderSide = 16384;
constexpr double kMaxRenderPixels = 64e6;

struct RenderOptions {
  int width = 640, height = 480;
  int supersample = 4;         // n x n samples where two boards or a board's outline meet.
  double blur_sigma_px = 0.0;  // Gaussian PSF; 0: none.
  // Sub-pixels per pixel side on which the blur is computed (header comment): 0 chooses
  // m = ceil(3 / blur_sigma_px), at most 8 (exact to < 5e-4 px of edge shift); 1 blurs the pixels
  // (fast; edges shift with their sub-pixel phase by up to 0.03 px at sigma = 0.5 px).
  int blur_grid = 0;
  double noise_sigma_gray = 0.0;  // Gaussian noise added before quantisation.
  double background_gray = 128.0;
  double black_gray = 20.0;
  double white_gray = 235.0;
  bool Check(std::string* why) const;
};

struct BoardView {
  AprilGrid grid;
  std::shared_ptr<const TagFamily> family;  // Must be grid.family's.
  Rigid3 cam_from_board;
};

// A camera's renderer: holds the pixel-corner ray table; Render() is const and thread-safe.
class FrameRenderer {
 public:
  // nullptr (and *why) for invalid intrinsics or options.
  static std::unique_ptr<FrameRenderer> Create(const CameraIntrinsics& intrinsics,
                                               const RenderOptions& options, std::string* why);
  // Renders the boards; `noise_rng` may be null when noise_sigma_gray = 0. Returns false and says
  // why for a family without enough codes for the grid's ids. `camera_now` (optional) renders
  // with other intrinsics than the table's (a calibration that changes over time): without
  // distortion the table's rays map affinely, n = A_now^-1 A n_table, at no cost; with distortion
  // a table for camera_now is built for the frame (30 ms at 640 x 480).
  bool Render(const std::vector<BoardView>& boards, Rng* noise_rng, GrayImage* image,
              std::string* why, const CameraIntrinsics* camera_now = nullptr) const;
  const RenderOptions& options() const { return options_; }
  // The sub-pixels per pixel side the blur is computed on (RenderOptions::blur_grid resolved).
  int BlurGrid() const { return fine_ ? fine_grid_ : 1; }

 private:
  FrameRenderer() = default;
  // The sharp, antialiased gray level of every pixel (no blur, noise or rounding) seen by
  // `camera` (this renderer's size; `ray_map` maps the table's rays to its rays), and the pixel box
  // [x0, x1) x [y0, y1) outside which the frame is the background.
  bool ShadePixels(const std::vector<BoardView>& views, const Eigen::Matrix3d& ray_map,
                   const CameraIntrinsics& camera, std::vector<float>* values,
                   std::array<int, 4>* boards_box, std::string* why) const;
  CameraIntrinsics intrinsics_;
  RenderOptions options_;
  // The homogeneous ray of the sample at pixel coordinates (u, v) (header comment, step 1; a_inv
  // = A^-1); false outside the lens's valid region.
  bool SampleRay(const Eigen::Matrix3d& a_inv, double u, double v, Eigen::Vector3d* ray) const;
  // With distortion: the rays of the (w + 1) x (h + 1) pixel corners, row-major, in two numbers
  // (header comment: on the plane z = 1, or stereographic for the omnidirectional families); NaN:
  // no valid ray. Empty without distortion (the rays are then affine in the pixel).
  std::vector<Eigen::Vector2d> corner_rays_;
  std::unique_ptr<const FrameRenderer> fine_;  // The m-times finer renderer of a blurred frame.
  int fine_grid_ = 1;
};

// One-off convenience: FrameRenderer::Create(...)->Render(...).
bool RenderFrame(const CameraIntrinsics& intrinsics, const std::vector<BoardView>& boards,
                 const RenderOptions& options, Rng* noise_rng, GrayImage* image, std::string* why);

// The sub-pixels per pixel side of the automatic blur grid for a PSF of `blur_sigma_px` (> 0):
// m = ceil(3 / sigma), at most 8 (edge shift < 5e-4 px; header comment).
int AutoBlurGrid(double blur_sigma_px);
// `m` lowered until a width x height image's grid m times finer has at most 16e6 sub-pixels (its
// ray table and buffers take ~30 bytes a sub-pixel): the memory bound of every blur grid.
int CapBlurGrid(int m, int width, int height);

// The camera of a grid m times finer than `camera`'s pixels (pixel-centre convention kept: fine
// pixel (i, j) of pixel (I, J) is centred at (m I + a, m J + b), a, b in 0..m-1).
CameraIntrinsics FinerCamera(const CameraIntrinsics& camera, int m);

// UndistortNormalized (the inverse of the lens) lives with the lens models in camera/camera.h.

}  // namespace calibench
