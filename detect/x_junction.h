// X-junction (checkerboard corner) refinement, in the image or through a camera's lens.
//
// At an X-junction q two straight edges cross; the image gradient g(p) at a pixel p on an edge is
// normal to that edge, which passes through q, so g(p) . (p - q) = 0 (Foerstner's corner operator,
// the equation cv::cornerSubPix solves). Over a window, in weighted least squares,
//     q = (sum_p w_p g_p g_p^T)^-1 sum_p w_p g_p g_p^T p,
// iterated with the window re-centred on q. Pixels off the edges (a blurred edge's flanks) add
// terms that cancel in pairs p, 2q - p when the window is point-symmetric about q, as the pattern
// is: the weight is a smooth function of the distance to q (a biweight that reaches 0 at
// radius_px), never a window cut at whole pixels.
//
// Through a lens, board lines are image curves: the constraint fails by the edge's sagitta,
// kappa |p - q|^2 / 2 for an edge of image curvature kappa, and q moves towards the edges' centres
// of curvature (0.01 px with a fisheye at 60 deg and a 6 px window). So, given a camera, every
// pixel is carried to a plane where lines of the board are straight whatever the lens: p -> t(p),
// and its gradient (a covector) -> (dt/dp)^-T g (dt/dp by central differences of t over the
// pixel grid). The weights are taken in that plane, scaled to pixels at the start, times each
// pixel's area there (|det dt/dp|), so that the sum stays an integral over a point-symmetric window
// of the plane. The solution is mapped back to a pixel through the lens. Two planes serve: the
// tangent plane about the start's ray (detect/tangent_plane.h; any direction, past 90 deg too) and
// the undistorted normalised plane z = 1 (an affine image of a pinhole's pixels). The blur is
// isotropic in pixels, not in the plane: where p -> t is not affine, the blurred edges' flanks are
// unequal and q moves (+0.003 px at 1 px blur for a pinhole seen through the tangent plane 15 deg
// off axis). So the plane is chosen per corner as the one nearer an affine map over the window (the
// change of dt/dp across it): the normalised plane for a pinhole, the tangent plane for a fisheye.
// The plane is fixed for the corner, so the window's plane points are computed again only when the
// window moves by a whole pixel.
// Without a camera t = p.
//
// Failures (false, *why): the window leaves the image, a pixel of it has no ray, the gradients
// do not span two directions (no junction: one edge, or a flat region), the estimate moves more
// than max_move_px from the start, or it does not settle within max_iterations.
#pragma once

#include <Eigen/Core>
#include <string>

#include "camera/camera.h"
#include "sim/render.h"

namespace calibench {

struct XJunctionOptions {
  // The weight's radius (biweight (1 - d^2 / R^2)^2): 6 px covers cornerSubPix's 11 x 11 window
  // of OpenCV's calibration sample; keep it below half the smallest square in pixels.
  double radius_px = 6.0;
  // The window follows q, so each iteration is a fixed-point step; it contracts fast where the
  // window holds one junction (5-15 iterations to 1e-4 px). A corner that needs more has other
  // structure in its window (squares under ~10 px): measured on rendered fisheye views, corners
  // that took 35-90 iterations were 0.08-0.5 px off, so they are refused.
  int max_iterations = 30;
  double tolerance_px = 1e-4;  // Stop when an iteration moves q by less.
  double max_move_px = 3.0;    // From the starting point; beyond it the junction was not there.
  // The image is smoothed by a Gaussian of this sigma before its gradients are taken (central
  // differences): the gradient of a sharp, pixel-integrated edge sampled at whole pixels depends
  // on the edge's sub-pixel phase, which biases each corner by up to 0.1 px on sharp frames.
  double gradient_sigma_px = 1.0;
  bool Check(std::string* why) const;
};

struct XJunctionSummary {
  bool converged = false;
  int iterations = 0;
  // The smallest over the largest eigenvalue of sum w g g^T at the last iteration: 1 for edges
  // crossing at right angles, about tan^2(theta / 2) for lines crossing at theta; a sheared
  // junction (thin squares of a tilted board) is poorly located along its bisector.
  double gradient_spread = 0;
  std::string message;  // Why it failed.
};

// Refines *corner (in: a start within max_move_px of the junction; out: the junction, pixel-centre
// convention of camera.h). `camera` (may be null): the lens the board is seen through. On failure
// *corner is unchanged.
XJunctionSummary RefineXJunction(const GrayImageView& image, const CameraIntrinsics* camera,
                                 const XJunctionOptions& options, Eigen::Vector2d* corner);

}  // namespace calibench
