// The photometric fit's machinery (detect/photometric_fit.h): the tag's layout of lines and
// rectangles, the model plane, the classification of a tag's pixels and the evaluation of the
// model's cost and Jacobian over them. Internal to detect/: photometric_fit.cc runs the fit,
// tag_fit_geometry.cc holds the layout, the model plane and the lines under a homography,
// tag_fit_pixels.cc the pixel work.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "detect/photometric_fit.h"
#include "detect/tag_model.h"
#include "detect/tangent_plane.h"

namespace calibench {
namespace photometric_internal {

constexpr int kNumParams = 13;  // G (8), sigma, black, white, shading (2).
constexpr int kSigma = 8, kBlack = 9, kWhite = 10, kShadeX = 11, kShadeY = 12;
using ParamVector = Eigen::Matrix<double, kNumParams, 1>;
using ParamMatrix = Eigen::Matrix<double, kNumParams, kNumParams>;
constexpr double kMinSigmaPx = 0.02;
constexpr double kReclassifyPx = 0.5;
constexpr double kReclassifySigmaPx = 0.1;  // Sigma may grow this much before (reach + 0.35 px).
constexpr int kMaxLinesPerPixel = 32;       // Cells of >= 1 px: a pixel is near far fewer.
// Slots of a rectangle's line that lies beyond the pixel's reach when it is classified: its profile
// is the constant 0 (the pixel is on the line's lower side) or 1 until the next classification.
constexpr uint8_t kSlotZero = kMaxLinesPerPixel, kSlotOne = kMaxLinesPerPixel + 1;
constexpr int kNumSlots = kMaxLinesPerPixel + 2;
// A pixel where the model's brightness moves by less than this fraction of the contrast per px
// of edge shift is flat (PixelResiduals): a Gaussian-blurred edge's slope phi(d / s) / s falls
// below it 2.15 s from the edge at s = 0.8 px, 2.04 s at 1, 1.78 s at 1.6, 1.40 s at 3.
constexpr double kFlatSlopePerPx = 0.05;
// With a camera the region's outline is sampled (8 points a side) and its box grown by this: it
// covers the chords between the samples.
constexpr double kOutlineMarginPx = 2;

// A line of the pattern in normalised tag coordinates: m . (x^, y^, 1) = 0, > 0 on the side of
// larger x (vertical lines) or y (horizontal lines).
struct TagLine {
  Eigen::Vector3d m;
  bool vertical;
};

// The pattern prepared for fitting: unique lines, rectangles as line indices.
struct Layout {
  std::vector<TagLine> lines;
  struct Rect {
    int x0, x1, y0, y1;  // Line indices.
  };
  std::vector<Rect> rects;
  std::array<int, 4> limits;  // The region's bounding lines x = -m, x = W + m, y = -m, y = W + m.
  std::array<Eigen::Vector2d, 4> region_corners;   // Normalised tag coordinates.
  int middle_vertical = 0, middle_horizontal = 0;  // Lines x = W / 2, y = W / 2 (for the tables).
};

Layout MakeLayout(const TagPattern& pattern);

// G from the 8 free parameters (G_22 = 1).
Eigen::Matrix3d HomographyOf(const ParamVector& x);

// The four corners (normalised pixel coordinates) of G: G c~ ~ q~ for q = (+-1, +-1).
bool CornersOf(const Eigen::Matrix3d& g, std::array<Eigen::Vector2d, 4>* corners);

// One pixel of the fit.
struct FitPixel {
  Eigen::Vector2d p;  // Normalised pixel coordinates.
  double gray;
  int first_line, num_lines;  // The lines within reach of it (pixel_lines_).
  int first_rect, num_rects;  // Its near rectangles as 4 slots of its lines (pixel_rects_).
  int deep;                   // Rectangles that contain it beyond the profile's reach.
  long key;                   // j * image width + i: which image pixel (the left-out set's key).
};
// x0, x1, y0, y1 among the pixel's lines (its lines within reach), or kSlotZero / kSlotOne.
using RectSlots = std::array<uint8_t, 4>;

// The pattern's lines under homography g, per line: raw l = G^T m (on the model plane), unit
// l / |l_xy|, scaled S l / |l_xy| (the signed distance in px without a camera: f = scaled . p^~),
// 1 / |l_xy|, and (l_x^2, 2 l_x l_y, l_y^2) for |M^T l_xy|^2 = (M M^T)_00 l_x^2 +
// 2 (M M^T)_01 l_x l_y + (M M^T)_11 l_y^2 with a camera.
struct PatternLines {
  std::vector<Eigen::Vector3d> raw, unit, scaled, squares;
  std::vector<double> inv_norm;
  // With a camera (BendLines): a line's image is curved, and blurring a curved edge moves its
  // mean-level crossing towards its centre of curvature. A pixel at distance f from the curve
  // sees the + side as a straight edge at f - kappa s_t^2 / 2 would show it, kappa the image
  // curvature (1/px, > 0 when the centre of curvature is on the + side), s_t^2 = sigma^2 + 1/12
  // the variance of the PSF and the pixel box along the edge (the first-order term of the
  // blurred disc, Phi(d/s) - (kappa s / 2) phi(d/s)). Per line: the shift kappa s_t^2 / 2 (px)
  // and its sigma-derivative kappa sigma. Empty without a camera.
  std::vector<double> bend_shift, bend_shift_dsigma;
  // With a camera: the first-order distance f = (l . p^~) / N(p), N = |M^T l_xy| taken at the
  // pixel, is not the distance d to the curve when N changes across it: f = d - spread d^2 / 2 with
  // spread = d ln N / d n (1/px, along the image normal towards +), so the profile is drawn at
  // d = f + spread f^2 / 2. Without it a least-squares fit reads the even error as an edge shift
  // of spread s_t^2 / 4 (the mean of d^2 under the profile's squared slope). Measured on noise-free
  // frames of a 190 deg unified lens (image-radial corner bias, 40-90 deg off the axis): +0.0002
  // to +0.0003 px without it, -0.0001 to -0.0002 px with it at blur 0.8 px; +0.0004 to +0.0011
  // -> -0.0004 to -0.0005 px at blur 1.6 px. What is left (inwards, growing as s_t^2) is not
  // explained. Per line, at its point nearest the tag's centre; empty without a camera.
  std::vector<double> spread;
};
// Per pixel, per line of its rectangles (slots 0..num_lines-1; kSlotZero/kSlotOne are the
// constants): P(f), P'(f), dP/dsigma(f), and d b / d f (weight; the constant slots collect unread
// weight). The profile is odd about one half: the far edge of a rectangle contributes 1 - P(f),
// so that [P(d_0) + P(d_1) - 1] = P(f_0) - P(f_1) with f the signed distance towards larger x
// (or y). Per line also its distance f (px) and image normal (unit, towards larger f), for the
// quadrant correction at the rectangles' vertices (tag_model.h), and with a camera 1 / N and
// r = M M^T l_xy / N, N = |M^T l_xy| (f = l . p^~ / N, d f / d l = (p^~ - f (r, 0)) / N).
struct PixelLines {
  std::array<EdgeProfileValue, kNumSlots> profile;
  std::array<double, kNumSlots> weight{};
  std::array<double, kMaxLinesPerPixel> distance;
  std::array<Eigen::Vector2d, kMaxLinesPerPixel> normal;
  std::array<double, kMaxLinesPerPixel> lens_inv_n;
  std::array<Eigen::Vector2d, kMaxLinesPerPixel> lens_r;
};

class TagFit {
 public:
  TagFit(const GrayImageView& image, const TagPattern& pattern, const PhotometricFitOptions& o,
         const CameraIntrinsics* camera)
      : image_(image),
        pattern_(pattern),
        options_(o),
        layout_(MakeLayout(pattern)),
        camera_(camera),
        a_inv_(camera ? Eigen::Matrix3d(camera->Matrix().inverse()) : Eigen::Matrix3d::Identity()) {
  }

  PhotometricFitResult Run(const std::array<Eigen::Vector2d, 4>& initial);

 private:
  // The fit's start from the detector's corners: the model plane (centre_, scale_, the tangent
  // plane with a camera), the homography through the corners, sigma = initial_blur_px, the pixels
  // classified and the levels from their medians. False with the failure set when the corners span
  // no quadrilateral, the region is unusable or its contrast is below min_contrast_gray.
  bool Start(const std::array<Eigen::Vector2d, 4>& initial, ParamVector* x,
             PhotometricFitResult* result);
  // Each pixel's gray - model (0 for a censored one) and whether the model is flat there (its
  // brightness changes by less than kFlatSlopePerPx of the contrast per px of edge shift), in
  // pixels_' order.
  struct PixelResiduals {
    std::vector<double> residual;
    std::vector<bool> flat;
  };
  // The fit's iterate: parameters; cost, J^T J, J^T r and the residuals where last evaluated (at x,
  // or one converged step before it); the tag's corners (model plane).
  struct FitState {
    ParamVector x;
    double cost = 0;
    ParamMatrix jtj;
    ParamVector jtr;
    PixelResiduals residuals;
    std::array<Eigen::Vector2d, 4> corners;
  };
  // Levenberg-Marquardt from *state (evaluated at its x) until the corners move by less than
  // convergence_px and sigma has settled, re-classifying the pixels when the corners or sigma move
  // past the margins; adds its iterations to result->iterations. False with the failure set when
  // it does not converge.
  bool Minimize(const std::array<Eigen::Vector2d, 4>& initial, FitState* state,
                PhotometricFitResult* result);
  // A trial step's corners and how far they moved (px) from the current ones and from those the
  // pixels were classified with. False when sigma exceeds max_blur_px or a corner leaves
  // 2 max_correction_px of the detector's.
  struct StepMoves {
    std::array<Eigen::Vector2d, 4> corners;
    double moved = 0, since_classified = 0;
  };
  bool StepCorners(const ParamVector& trial, const std::array<Eigen::Vector2d, 4>& initial,
                   const std::array<Eigen::Vector2d, 4>& corners, StepMoves* moves) const;
  // The robust pass (photometric_fit.h, "Pixels that disagree"): from a converged *state, leaves
  // out the flat pixels that disagree, their rim and the neighbours that disagree, and fits again,
  // until none is left out or after max_outlier_rounds. False with the failure set when too much
  // of the region is left out or a re-fit fails.
  bool LeaveOutDisagreeingPixels(const std::array<Eigen::Vector2d, 4>& initial, FitState* state,
                                 PhotometricFitResult* result);
  // Fills the result's levels, blur and residual RMS and *pixel_corners; false with the failure
  // set for a contrast too low for the residuals or a corner moved past max_correction_px.
  bool CheckSolution(const FitState& state, const std::array<Eigen::Vector2d, 4>& initial,
                     double dof, std::array<Eigen::Vector2d, 4>* pixel_corners,
                     PhotometricFitResult* result) const;
  // Each corner's covariance and crlb_px at the solution (header of photometric_fit.h): the
  // corners are functions of G, cov = D_k [residual_variance (J^T J)^-1]_GG D_k^T.
  void CornerCovariances(const ParamVector& x, const ParamMatrix& jtj, double residual_variance,
                         const std::array<Eigen::Vector2d, 4>& corners,
                         PhotometricFitResult* result) const;
  // The region (the black square and its white margin) in the image under homography g: its box
  // in pixels (grown by kOutlineMarginPx with a camera) and, with a camera, its outline. False
  // with the failure set for a degenerate homography, a region across its horizon, or one larger
  // than 4096 px.
  struct RegionBox {
    double u0, u1, v0, v1;
    std::vector<Eigen::Vector2d> outline;
  };
  bool RegionInImage(const Eigen::Matrix3d& g, RegionBox* box, PhotometricFitResult* result) const;
  // Selects the pixels for parameters x (classification radius from sigma). False with the
  // failure set when the region is unusable.
  bool Classify(const ParamVector& x, PhotometricFitResult* result);
  // The pattern's lines under g (PatternLines); false when a line's |l_xy| <= min_norm (a
  // degenerate homography).
  bool LinesUnder(const Eigen::Matrix3d& g, double min_norm, PatternLines* lines) const;
  // With a camera, PatternLines::bend_shift and bend_shift_dsigma for PSF sigma: each line's
  // image curvature at its point nearest the tag's centre (second differences of ToPixel); and
  // its spread there (central differences of ln N across the line).
  void BendLines(double sigma, PatternLines* lines) const;
  // Narrows [*lo, *hi] to row j's part of the region: the outline's span (with a camera) or the
  // span inside the four limit lines, each linear in i along the row (without).
  void RowSpan(int j, const RegionBox& region, bool outline_spans, const PatternLines& lines,
               double reach, double* lo, double* hi) const;
  // A pixel of the region: (i, j), its model point p^~ and d p^ / d pixel.
  struct PixelAt {
    int i, j;
    Eigen::Vector3d p;
    Eigen::Matrix2d m;
  };
  // Lines within near_px of a pixel get a profile slot; a pixel is kept when a rectangle's border
  // is within include_px of it.
  struct ClassifyMargins {
    double near_px, include_px;
  };
  // Keeps the pixel (with its line slots and rectangles) when some rectangle's border is near.
  // *line_values: each line's signed distance (px) at the pixel; with a camera computed here.
  void AddPixel(const PixelAt& at, const PatternLines& lines, const ClassifyMargins& margins,
                std::vector<double>* line_values);
  // False with the failure set when too much of the region is outside the image or too few
  // pixels were kept.
  bool EnoughPixels(long inside, long outside, PhotometricFitResult* result) const;
  // Cost, J^T J and J^T r at x, and each pixel's residual; false when x is invalid (a pixel behind
  // the homography's horizon).
  bool Evaluate(const ParamVector& x, double* cost, ParamMatrix* jtj, ParamVector* jtr,
                PixelResiduals* residuals) const;
  // Fills the distance, normal and profile (tables: vertical, horizontal lines) of each line of
  // pixel `index` at its model point p^~ (and the lens terms with a camera).
  void ProfileLines(size_t index, const Eigen::Vector3d& p, const PatternLines& lines,
                    const std::array<EdgeProfileTable, 2>& tables, PixelLines* out) const;
  // d b / d G_ij = sum over lines of weight m_i (d f / d l_j), m = (1, 0, m_2) for vertical lines
  // and (0, 1, m_2) for horizontal ones (the model's gradient is this times shade * contrast).
  Eigen::Matrix3d HomographyGradient(size_t index, const Eigen::Vector3d& p,
                                     const PatternLines& lines, const PixelLines& pl) const;
  bool InitialHomography(const std::array<Eigen::Vector2d, 4>& corners, ParamVector* x) const;
  // The model plane: pixels themselves, or with a camera the tangent plane about the tag's centre
  // ray (tangent_plane.h), where the tag's edges are straight. p^ = (model point - centre_) /
  // scale_. False where the pixel has no ray in front of that plane.
  bool ModelOf(const Eigen::Vector2d& pixel, Eigen::Vector2d* p_hat) const;
  // With a camera: whether the pixel position has a ray (inside the lens's valid region), and
  // that ray (unit) when `ray` is given.
  bool HasRay(const Eigen::Vector2d& pixel, Eigen::Vector3d* ray = nullptr) const;
  // With a camera: whether every pixel position within `radius` px of `pixel` (its 8 neighbours at
  // that distance; the valid region is a convex disc in pixels for every family) has a ray.
  bool RaysAround(const Eigen::Vector2d& pixel, double radius) const;
  // d pixel / d p^ at a model point (scale_ I without a camera), and its inverse d p^ / d pixel.
  Eigen::Matrix2d PixelJacobian(const Eigen::Vector2d& p_hat) const;
  Eigen::Matrix2d ModelJacobian(const Eigen::Vector2d& p_hat) const {
    return PixelJacobian(p_hat).inverse();
  }
  Eigen::Vector2d ToPixel(const Eigen::Vector2d& p_hat) const;
  // Pixels per unit of p^ at the tag's centre (for the step and re-classification thresholds).
  double PixelsPerUnit() const { return px_per_unit_; }

  const GrayImageView& image_;
  const TagPattern& pattern_;
  const PhotometricFitOptions& options_;
  const Layout layout_;
  const CameraIntrinsics* camera_;  // Null: a pinhole tag, straight edges in the image.
  const Eigen::Matrix3d a_inv_;     // A^-1 of the camera (pixel -> ray: RayOfDistorted).
  TangentPlane plane_;              // With a camera: the model plane (Run sets it).
  Eigen::Vector2d centre_ = Eigen::Vector2d::Zero();
  double scale_ = 1, px_per_unit_ = 1;
  Eigen::Matrix2d centre_jacobian_ = Eigen::Matrix2d::Identity();  // ModelJacobian(0).
  std::vector<FitPixel> pixels_;
  std::vector<Eigen::Matrix2d> pixel_jacobians_;  // With a camera: ModelJacobian per pixel.
  std::vector<int> pixel_lines_;
  std::vector<RectSlots> pixel_rects_;
  std::vector<long> left_out_;  // Sorted FitPixel::key of the pixels the robust pass left out.
  long left_out_pixels_ = 0;    // Pixels of the region Classify dropped as left out.
  std::array<Eigen::Vector2d, 4> classified_corners_;
  double classified_sigma_ = 0;
};

}  // namespace photometric_internal
}  // namespace calibench
