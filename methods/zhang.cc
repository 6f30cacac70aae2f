// Methods `zhang` and `zhang_handeye`: Zhang's method (cv::calibrateCamera, batch/zhang.h) on the
// (frame, board) views of a scenario with planar boards, then the constant extrinsic from the
// per-view board poses (batch/extrinsic_from_views.h):
//   zhang          by chordal rotation averaging with the known body motion and board placement;
//   zhang_handeye  by hand-eye calibration (Tsai-Lenz) on board 0: only the body motion needed.
// Both share one calibrateCamera per trial (for equal options). Views: every view_stride-th frame,
// thinned further to at most max_views (frame, board) views (calibrateCamera grows as N^2.5); a
// board seen with fewer than kMinViewPoints points in a frame gives no view. The estimate reports
// OpenCV's standard deviations and its own reprojection RMS (one pose per view: fit_rms_px).
// Online mode (window_s, every_s): methods/online.h (calibrateCamera starts from scratch on each
// window). With model unified, eucm or double-sphere, the per-view solve is the wide start
// (batch/wide_init.h: no standard deviations); with a radtan or equidistant model on a camera of
// those families (MethodInput::lens) it refuses (RefuseWideLens).
#include "batch/zhang.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "batch/extrinsic_from_views.h"
#include "batch/wide_init.h"
#include "methods/method.h"
#include "methods/online.h"
#include "methods/options.h"
#include "util/opencv_threads.h"

namespace calibench {
namespace {

struct ZhangSettings {
  LensModel model = LensModel::kPinholeK2;
  int view_stride = 1;  // Use every view_stride-th frame.
  int max_views = 60;   // Cap on (frame, board) views; 0: all.
  OnlineOptions online;

  void Visit(OptionVisitor* v) {
    v->Field({"model", "",
              "Lens model of the calibration (`pinhole-equi`: cv::fisheye::calibrate; unified, "
              "eucm, double-sphere: the wide start)."},
             &model);
    v->Field({"view_stride", "", "Use every view_stride-th frame."}, &view_stride);
    v->Field({"max_views", "",
              "Cap on (frame, board) views, reached by a larger stride (calibrateCamera grows as "
              "N^2.5); 0: all."},
             &max_views);
    online.Visit(v);
  }
  bool Check(std::string* why) const {
    std::string msg;
    if (view_stride < 1) msg = "view_stride must be >= 1";
    if (max_views < 0) msg = "max_views must be >= 0 (0: all)";
    if (msg.empty()) return online.Check(why);
    if (why) *why = msg;
    return false;
  }
};

// One calibrateCamera on a trial's views, and what both extrinsic estimates need from it.
struct ZhangSolve {
  ZhangResult result;
  std::string message;                          // Why it failed, or the note both rows carry.
  std::vector<Rigid3> parent_from_cam_views;    // Per used view, from the known board placement.
  std::vector<Rigid3> parent_from_points0;      // Board 0's views: the points frame's pose...
  std::vector<Rigid3> cam_from_board0;          // ... and the board's pose in the camera.
  long frames_used = 0, observations_used = 0;  // Of the used views.
  std::shared_ptr<const PerViewSolution> per_view;  // The used views, for a ceres twin.
};

// The (frame, board) views of every stride-th frame (stride grown to keep at most max_views), each
// board's points in its own frame; a board with fewer than kMinViewPoints points gives none.
// view_time_board: per view, its frame's time and its board.
void CollectViews(const MethodInput& input, const ZhangSettings& settings, std::vector<View>* views,
                  std::vector<std::pair<double, int>>* view_time_board) {
  constexpr size_t kMinViewPoints = 8;
  const std::vector<BoardLayout>& layouts = input.boards;
  const FrameSet& frames = input.Frames();
  int stride = settings.view_stride;
  const int num_frames = static_cast<int>(frames.views.size());
  const int boards = static_cast<int>(layouts.size());
  if (settings.max_views > 0) {
    stride = std::max(stride, (num_frames * boards + settings.max_views - 1) / settings.max_views);
  }
  for (int k = 0; k < num_frames; k += stride) {
    std::vector<View> by_board(boards);
    for (size_t i = 0; i < frames.point_ids[k].size(); ++i) {
      const int id = frames.point_ids[k][i];
      for (int b = boards - 1; b >= 0; --b) {
        if (id < layouts[b].first_point) continue;
        by_board[b].points.push_back(layouts[b].corners_in_board[id - layouts[b].first_point]);
        by_board[b].pixels.push_back(frames.views[k].pixels[i]);
        break;
      }
    }
    for (int b = 0; b < boards; ++b) {
      if (by_board[b].points.size() < kMinViewPoints) continue;
      views->push_back(std::move(by_board[b]));
      view_time_board->emplace_back(frames.times_s[k], b);
    }
  }
}

// calibrateCamera (or cv::fisheye) on the views; for the omnidirectional families the wide start
// (batch/wide_init.h), which OpenCV has not (no standard deviations).
ZhangResult Calibrate(const std::vector<View>& views, const MethodInput& input, LensModel model) {
  if (WideInitServes(FamilyOf(model)) && FamilyOf(model) != LensFamily::kEquidistant) {
    WideInitOptions wide;
    wide.model = model;
    wide.image_width = input.image_width;
    wide.image_height = input.image_height;
    return FromWideStart(InitializeWideCamera(views, wide));
  }
  ZhangOptions options;
  options.model = model;
  options.image_width = input.image_width;
  options.image_height = input.image_height;
  return CalibrateZhang(views, options);
}

// Places each used view in the parent frame through the known board motion: the camera's pose
// per view, board 0's poses for hand-eye, and the per-view solution a ceres twin starts from.
void PlaceViews(const MethodInput& input, const std::vector<View>& views,
                const std::vector<std::pair<double, int>>& view_time_board, ZhangSolve* solve) {
  const std::vector<BoardLayout>& layouts = input.boards;
  const ZhangResult& z = solve->result;
  auto per_view = std::make_shared<PerViewSolution>();
  std::set<double> frame_times;
  for (size_t i = 0; i < z.used_views.size(); ++i) {
    const auto [time, b] = view_time_board[z.used_views[i]];
    const Rigid3 parent_from_points = input.parent_from_points(time);
    const Rigid3 parent_from_board = parent_from_points * layouts[b].points_from_board;
    solve->parent_from_cam_views.push_back(parent_from_board * z.cam_from_board[i].Inverse());
    frame_times.insert(time);
    solve->observations_used += static_cast<long>(views[z.used_views[i]].pixels.size());
    per_view->views.push_back(views[z.used_views[i]]);
    per_view->cam_from_board.push_back(z.cam_from_board[i]);
    per_view->parent_from_board.push_back(parent_from_board);
    if (b == 0) {
      // Hand-eye sees board 0 as the target, moving with the points frame.
      solve->parent_from_points0.push_back(parent_from_points);
      solve->cam_from_board0.push_back(z.cam_from_board[i] *
                                       Rigid3{layouts[0].points_from_board.Inverse()});
    }
  }
  solve->frames_used = static_cast<long>(frame_times.size());
  solve->per_view = std::move(per_view);
  solve->message = z.message + "; " + std::to_string(views.size()) + " views";
}

ZhangSolve Solve(const MethodInput& input, const ZhangSettings& settings) {
  ZhangSolve solve;
  MethodResult refused;
  if (!WideInitServes(FamilyOf(settings.model)) ||
      FamilyOf(settings.model) == LensFamily::kEquidistant) {
    if (RefuseWideLens(input, std::string("zhang (model ") + ToString(settings.model) + ")",
                       &refused)) {
      solve.result.status = MethodStatus::kFailed;
      solve.message = refused.message;
      return solve;
    }
  }
  const std::vector<BoardLayout>& layouts = input.boards;
  if (layouts.empty()) {
    solve.message = "zhang needs planar boards: points: {boards: [...]} or {aprilgrids: [...]}";
    solve.result.status = MethodStatus::kFailed;
    return solve;
  }
  std::vector<View> views;
  std::vector<std::pair<double, int>> view_time_board;
  CollectViews(input, settings, &views, &view_time_board);
  solve.result = Calibrate(views, input, settings.model);
  if (!solve.result.IsUsable()) {
    solve.message = solve.result.message;
    return solve;
  }
  PlaceViews(input, views, view_time_board, &solve);
  return solve;
}

// The shared part of both types: options, the cached solve, the estimate's intrinsics.
class ZhangBase : public Method {
 public:
  // OpenCV's own thread pool splits calibrateCamera's sums differently from run to run; the
  // harness parallelises over trials instead. Instances are made while a configuration is read,
  // before any worker thread starts (util/opencv_threads.h).
  ZhangBase() { UseSequentialOpenCv(); }
  void VisitOptions(OptionVisitor* v) override { settings_.Visit(v); }
  bool Check(std::string* why) const override { return settings_.Check(why); }

 protected:
  // The solve for these settings, computed once per trial; *result gets its status, message, wall
  // time, intrinsics, standard deviations and fit RMS.
  const ZhangSolve& SharedSolve(const MethodInput& input, MethodResult* result) const {
    // Per window in online mode: the trial's cache outlives the windows.
    const ZhangSolve& solve = input.cache->Get<ZhangSolve>(
        "zhang:" + OptionsKey(*this) + input.WindowKey(), [&] { return Solve(input, settings_); });
    result->status = solve.result.status;
    result->message = solve.message;
    result->wall_ms = solve.result.wall_ms;
    if (!solve.result.IsUsable()) return solve;
    CameraEstimate& e = result->estimate;
    e.intrinsics = solve.result.intrinsics;
    e.lens = settings_.model;
    e.intrinsics_std = solve.result.intrinsics_std;
    e.fit_rms_px = solve.result.rms_reproj_px;
    result->frames_used = solve.frames_used;
    result->observations_used = solve.observations_used;
    result->per_view = solve.per_view;
    return solve;
  }
  static void SetExtrinsic(const Rigid3& parent_from_cam, CameraEstimate* e) {
    e->has_camera = true;
    e->parent_from_cam = parent_from_cam;
    e->cam_from_parent = parent_from_cam.Inverse();
  }
  // Runs SolveOn statically or on windows (online mode).
  MethodResult RunMode(const MethodInput& input, EstimateSink* sink) const {
    return RunMaybeOnline(
        input, settings_.online, sink,
        [this](const MethodInput& window, const CameraEstimate*) { return SolveOn(window); });
  }
  virtual MethodResult SolveOn(const MethodInput& input) const = 0;

 private:
  ZhangSettings settings_;
};

class ZhangMethod final : public ZhangBase {
 public:
  std::unique_ptr<Method> Clone() const override { return std::make_unique<ZhangMethod>(*this); }
  MethodResult Run(const MethodInput& input, EstimateSink* sink) const override {
    return RunMode(input, sink);
  }
  MethodResult SolveOn(const MethodInput& input) const override {
    MethodResult result;
    const ZhangSolve& solve = SharedSolve(input, &result);
    if (result.IsUsable())
      SetExtrinsic(AveragePoses(solve.parent_from_cam_views), &result.estimate);
    return result;
  }
};

class ZhangHandEyeMethod final : public ZhangBase {
 public:
  std::unique_ptr<Method> Clone() const override {
    return std::make_unique<ZhangHandEyeMethod>(*this);
  }
  MethodResult Run(const MethodInput& input, EstimateSink* sink) const override {
    return RunMode(input, sink);
  }
  MethodResult SolveOn(const MethodInput& input) const override {
    MethodResult result;
    const ZhangSolve& solve = SharedSolve(input, &result);
    if (!result.IsUsable()) return result;
    Rigid3 hand_eye;
    std::string why;
    if (!HandEyeTsai(solve.parent_from_points0, solve.cam_from_board0, &hand_eye, &why)) {
      result.status = MethodStatus::kFailed;
      result.message = why;
      return result;
    }
    SetExtrinsic(hand_eye, &result.estimate);
    return result;
  }
};

}  // namespace

std::unique_ptr<Method> MakeZhangMethod() { return std::make_unique<ZhangMethod>(); }
std::unique_ptr<Method> MakeZhangHandEyeMethod() { return std::make_unique<ZhangHandEyeMethod>(); }

}  // namespace calibench
