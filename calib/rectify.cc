#include "calib/rectify.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <tuple>
#include <utility>

namespace calibench {
namespace {

// The pixel the lens of `k` shows the ray `ray_in_cam` at, inside the image (pixel centres at
// integers: [-0.5, w - 0.5]) and where the lens is one-to-one; false otherwise.
bool SourcePixel(const RigCamera& camera, const Eigen::Vector3d& ray_in_cam, Eigen::Vector2d* q) {
  if (!camera.intrinsics.DistortionIsMonotoneAlong(ray_in_cam)) return false;
  if (!ProjectPoint(camera.intrinsics, ray_in_cam, q) || !q->allFinite()) return false;
  if (camera.image_width <= 0) return true;
  return q->x() >= -0.5 && q->y() >= -0.5 && q->x() <= camera.image_width - 0.5 &&
         q->y() <= camera.image_height - 0.5;
}

// Every border pixel of the rectified image with focal length f has a source in both cameras.
bool BorderInside(const CameraRig& rig, const Rectification& r, double f) {
  const RigCamera* cameras[2] = {&rig.cameras[r.camera_a], &rig.cameras[r.camera_b]};
  const Eigen::Matrix3d* rotations[2] = {&r.rect_from_cam_a, &r.rect_from_cam_b};
  const double w = r.width - 1, h = r.height - 1;
  for (int i = 0; i <= std::max(r.width, r.height); ++i) {
    const double u = std::min<double>(i, w), v = std::min<double>(i, h);
    const Eigen::Vector2d border[4] = {{u, 0}, {u, h}, {0, v}, {w, v}};
    for (const Eigen::Vector2d& pixel : border) {
      const Eigen::Vector3d ray_rect((pixel.x() - r.cx_px) / f, (pixel.y() - r.cy_px) / f, 1.0);
      for (int c = 0; c < 2; ++c) {
        Eigen::Vector2d q;
        if (!SourcePixel(*cameras[c], rotations[c]->transpose() * ray_rect, &q)) return false;
      }
    }
  }
  return true;
}

}  // namespace

bool RectifyOptions::Check(std::string* why) const {
  const auto fail = [&](const std::string& message) {
    if (why) *why = message;
    return false;
  };
  if (camera_a < 0 || camera_b < 0 || camera_a == camera_b) {
    return fail("camera_a, camera_b: two different camera indices");
  }
  if (!(f_min_scale > 0 && f_max_scale > f_min_scale)) {
    return fail("f_min_scale, f_max_scale: 0 < f_min_scale < f_max_scale");
  }
  return true;
}

Eigen::Matrix<double, 3, 4> Rectification::P1() const {
  Eigen::Matrix<double, 3, 4> p = Eigen::Matrix<double, 3, 4>::Zero();
  p(0, 0) = p(1, 1) = f_px;
  p(0, 2) = cx_px;
  p(1, 2) = cy_px;
  p(2, 2) = 1;
  return p;
}

Eigen::Matrix<double, 3, 4> Rectification::P2() const {
  Eigen::Matrix<double, 3, 4> p = P1();
  p(0, 3) = f_px * baseline_x;
  return p;
}

Eigen::Matrix4d Rectification::Q() const {
  Eigen::Matrix4d q = Eigen::Matrix4d::Zero();
  q(0, 0) = q(1, 1) = 1;
  q(0, 3) = -cx_px;
  q(1, 3) = -cy_px;
  q(2, 3) = f_px;
  q(3, 2) = -1.0 / baseline_x;
  return q;
}

RectifySummary RectifyPair(const CameraRig& rig, const RectifyOptions& options) {
  RectifySummary summary;
  std::string why;
  if (!options.Check(&why)) {
    summary.error = "rectify options: " + why;
    return summary;
  }
  if (options.camera_a >= rig.NumCameras() || options.camera_b >= rig.NumCameras()) {
    summary.error = "rectify: the rig has " + std::to_string(rig.NumCameras()) +
                    " cameras, asked for " + std::to_string(options.camera_a) + " and " +
                    std::to_string(options.camera_b);
    return summary;
  }
  if (!rig.Check(&why)) {
    summary.error = "rectify: " + why;
    return summary;
  }
  const RigCamera& a = rig.cameras[options.camera_a];
  const RigCamera& b = rig.cameras[options.camera_b];
  if (a.image_width <= 0) {
    const std::string name = a.name.empty() ? "camera " + std::to_string(options.camera_a) : a.name;
    summary.error = "rectify: " + name + ": image size unknown (the rectified images take it)";
    return summary;
  }
  Rectification& r = summary.rectification;
  r.camera_a = options.camera_a;
  r.camera_b = options.camera_b;
  r.width = a.image_width;
  r.height = a.image_height;
  r.cx_px = (r.width - 1) / 2.0;
  r.cy_px = (r.height - 1) / 2.0;

  // Bouguet's split (header comment).
  const Rigid3 b_from_a = rig.CamFromCam(options.camera_b, options.camera_a);
  const Eigen::Matrix3d r_half = ExpSO3(-0.5 * LogSO3(b_from_a.rotation));
  const Eigen::Vector3d t = r_half * b_from_a.translation;
  const double s = t.x() >= 0 ? 1.0 : -1.0;
  const Eigen::Vector3d axis = t.cross(Eigen::Vector3d(s, 0, 0));
  Eigen::Matrix3d w_r = Eigen::Matrix3d::Identity();
  if (axis.norm() > 0) {
    const double angle = std::acos(std::min(1.0, std::abs(t.x()) / t.norm()));
    w_r = ExpSO3(axis.normalized() * angle);
  }
  r.rect_from_cam_a = w_r * r_half.transpose();
  r.rect_from_cam_b = w_r * r_half;
  r.baseline_x = (w_r * t).x();

  // The focal length rule (header comment): bisection on log f.
  const double f_mean = 0.5 * (a.intrinsics.fkv_px + b.intrinsics.fkv_px);
  double lo = std::log(options.f_min_scale * f_mean), hi = std::log(options.f_max_scale * f_mean);
  if (!BorderInside(rig, r, std::exp(hi))) {
    summary.error = "rectify: no rectified view of " + std::to_string(r.width) + " x " +
                    std::to_string(r.height) +
                    " px lies inside both images (do the cameras look the same way?)";
    return summary;
  }
  if (BorderInside(rig, r, std::exp(lo))) {
    hi = lo;
  } else {
    for (int i = 0; i < 60 && hi - lo > 1e-9; ++i) {
      const double mid = 0.5 * (lo + hi);
      (BorderInside(rig, r, std::exp(mid)) ? hi : lo) = mid;
    }
  }
  r.f_px = std::exp(hi);
  summary.ok = true;
  return summary;
}

RectifyMap RectifyMaps(const CameraRig& rig, const Rectification& r, int which) {
  const RigCamera& camera = rig.cameras[which == 0 ? r.camera_a : r.camera_b];
  const Eigen::Matrix3d cam_from_rect =
      (which == 0 ? r.rect_from_cam_a : r.rect_from_cam_b).transpose();
  RectifyMap map;
  map.width = r.width;
  map.height = r.height;
  map.x.resize(static_cast<size_t>(r.width) * r.height);
  map.y.resize(map.x.size());
  for (int v = 0; v < r.height; ++v) {
    float* mx = map.x.data() + static_cast<size_t>(v) * r.width;
    float* my = map.y.data() + static_cast<size_t>(v) * r.width;
    for (int u = 0; u < r.width; ++u) {
      const Eigen::Vector3d ray_rect((u - r.cx_px) / r.f_px, (v - r.cy_px) / r.f_px, 1.0);
      Eigen::Vector2d q;
      const Eigen::Vector3d ray = cam_from_rect * ray_rect;
      const bool ok = camera.intrinsics.DistortionIsMonotoneAlong(ray) &&
                      ProjectPoint(camera.intrinsics, ray, &q) && q.allFinite();
      mx[u] = ok ? static_cast<float>(q.x()) : -1.f;
      my[u] = ok ? static_cast<float>(q.y()) : -1.f;
    }
  }
  return map;
}

GrayImage RectifiedPairImage(const CameraRig& rig, const Rectification& r, const GrayImage& image_a,
                             const GrayImage& image_b, int line_spacing_px) {
  cv::Mat out(r.height, 2 * r.width, CV_8UC1, cv::Scalar(0));
  const GrayImage* images[2] = {&image_a, &image_b};
  for (int which = 0; which < 2; ++which) {
    const GrayImage& image = *images[which];
    if (image.width <= 0 || image.height <= 0) continue;
    const cv::Mat source(image.height, image.width, CV_8UC1,
                         const_cast<uint8_t*>(image.pixels.data()));
    RectifyMap map = RectifyMaps(rig, r, which);
    const cv::Mat map_x(map.height, map.width, CV_32FC1, map.x.data());
    const cv::Mat map_y(map.height, map.width, CV_32FC1, map.y.data());
    cv::Mat half = out(cv::Rect(which * r.width, 0, r.width, r.height));
    cv::remap(source, half, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
  }
  if (line_spacing_px > 0) {
    constexpr int kDashPx = 8;
    for (int v = line_spacing_px / 2; v < out.rows; v += line_spacing_px) {
      uint8_t* row = out.ptr<uint8_t>(v);
      for (int u = 0; u < out.cols; ++u) row[u] = (u / kDashPx) % 2 == 0 ? 255 : 0;
    }
  }
  GrayImage image;
  image.width = out.cols;
  image.height = out.rows;
  image.pixels.assign(out.data, out.data + out.total());
  return image;
}

VerticalDisparity MeasureVerticalDisparity(const CameraRig& rig, const Rectification& r,
                                           const std::vector<RigFrame>& frames) {
  VerticalDisparity result;
  const int cams[2] = {r.camera_a, r.camera_b};
  const Eigen::Matrix3d* rotations[2] = {&r.rect_from_cam_a, &r.rect_from_cam_b};
  // The rectified row of a pixel of camera `which`; false when it has no ray in front.
  const auto row = [&](int which, const Eigen::Vector2d& pixel, double* v) {
    Eigen::Vector3d ray;
    if (!UnprojectToRay(rig.cameras[cams[which]].intrinsics, pixel, &ray)) return false;
    const Eigen::Vector3d p = *rotations[which] * ray;
    if (!(p.z() > 0)) return false;
    *v = r.f_px * p.y() / p.z() + r.cy_px;
    return true;
  };
  const auto key = [](const Eigen::Vector3d& x) { return std::make_tuple(x.x(), x.y(), x.z()); };
  double sum2 = 0;
  for (const RigFrame& frame : frames) {
    if (static_cast<int>(frame.views_by_camera.size()) <= std::max(cams[0], cams[1])) continue;
    const View& va = frame.views_by_camera[cams[0]];
    const View& vb = frame.views_by_camera[cams[1]];
    std::map<std::tuple<double, double, double>, Eigen::Vector2d> pixel_b;
    for (size_t i = 0; i < vb.points.size() && i < vb.pixels.size(); ++i) {
      pixel_b[key(vb.points[i])] = vb.pixels[i];
    }
    for (size_t i = 0; i < va.points.size() && i < va.pixels.size(); ++i) {
      const auto it = pixel_b.find(key(va.points[i]));
      double v_a = 0, v_b = 0;
      if (it == pixel_b.end() || !row(0, va.pixels[i], &v_a) || !row(1, it->second, &v_b)) {
        continue;
      }
      const double d = v_a - v_b;
      sum2 += d * d;
      result.max_px = std::max(result.max_px, std::abs(d));
      ++result.points;
    }
  }
  if (result.points > 0) result.rms_px = std::sqrt(sum2 / result.points);
  return result;
}

}  // namespace calibench
