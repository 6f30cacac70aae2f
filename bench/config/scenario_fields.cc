// The scenario format, declared once (fields.h): each field's YAML key, member, type, default (the
// member's initializer), unit, doc and check. The parser, the writer, equality, the key lists of
// "did you mean", the sweepable keys and docs/configuration.md are derived from these functions.
// How the measurements are made (noise, rendering, detection, diagnostics): source_fields.cc.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "bench/config/scenario.h"
#include "metrics/tracking.h"
#include "sim/synthetic.h"
#include "sim/tag_family.h"

namespace calibench {
namespace {

bool PositiveFinite(double v, std::string* why) {
  if (v > 0 && std::isfinite(v)) return true;
  *why = "must be positive and finite";
  return false;
}

std::string Integer(double v) { return std::to_string(static_cast<long>(v)); }

const EnumNames<CalibrationCase>& CaseNames() {
  static const EnumNames<CalibrationCase> names{
      {{CalibrationCase::kFixedCamera, "fixed_camera"},
       {CalibrationCase::kMovingCamera, "moving_camera"}}};
  return names;
}

// Every family of the list (camera/lens_families.h), by its name.
const EnumNames<LensFamily>& ScenarioLensFamilies() {
  static const EnumNames<LensFamily> names = [] {
    EnumNames<LensFamily> n{{}, "lens family"};
    for (const LensFamilyInfo& info : LensFamilies())
      n.entries.emplace_back(info.family, info.name);
    return n;
  }();
  return names;
}

// The frame of a twist as written; auto: world for a fixed camera, body for a moving one.
enum class MotionFrame { kAuto, kBody, kWorld };
const EnumNames<MotionFrame>& MotionFrameNames() {
  static const EnumNames<MotionFrame> names{
      {{MotionFrame::kAuto, "auto"}, {MotionFrame::kBody, "body"}, {MotionFrame::kWorld, "world"}}};
  return names;
}

void VisitMotion(FieldVisitor& v, ScenarioConfig& s) {
  // The preset's name as written (read only: the twist it sets is what is written and compared).
  static const EnumNames<ThesisMotion> presets{ThesisMotionNames()};
  std::string preset = s.motion_preset ? presets.Name(*s.motion_preset) : "";
  Choices choices = presets.AsChoices();
  choices.first_is_unset = false;  // "none" is a preset (no motion), not the absence of one.
  v.Field({"preset", "",
           "A thesis motion (body twist for a moving camera; the equivalent spatial "
           "twist for a fixed one) instead of the components.",
           "", nullptr, kNotWritten | kNotCompared},
          &preset, choices);
  ThesisMotion read;
  if (v.Reads() && presets.Parse(preset, &read)) s.motion_preset = read;
  TwistProfile& m = s.motion;
  v.Field({"v_const", "m/s", "Linear velocity: v(t) = v_const + v_cos cos(ft) + v_sin sin(ft)."},
          &m.v_const);
  v.Field({"v_cos", "m/s", "Linear velocity, cosine term."}, &m.v_cos);
  v.Field({"v_sin", "m/s", "Linear velocity, sine term."}, &m.v_sin);
  v.Field({"w_const", "rad/s", "Angular velocity, likewise."}, &m.w_const);
  v.Field({"w_cos", "rad/s", "Angular velocity, cosine term."}, &m.w_cos);
  v.Field({"w_sin", "rad/s", "Angular velocity, sine term."}, &m.w_sin);
  v.Field({"frequency_rad_s", "rad/s", "f above."}, &m.frequency_rad_s);
  MotionFrame frame = v.Reads()                                ? MotionFrame::kAuto
                      : m.frame == TwistProfile::Frame::kWorld ? MotionFrame::kWorld
                                                               : MotionFrame::kBody;
  VisitEnum(
      v,
      {"frame", "", "Frame of the twist; auto: world for a fixed camera, body for a moving one."},
      &frame, MotionFrameNames());
  v.Field({"random_phase", "",
           "Each trial starts the profile at its own phase (drawn from the "
           "trial seed), so trials differ in their views, not only in noise."},
          &s.motion_random_phase);
  v.Exclusive(
      "preset",
      {"v_const", "v_cos", "v_sin", "w_const", "w_cos", "w_sin", "frequency_rad_s", "frame"},
      "give either a preset or the components");
  v.Check(nullptr, [&s, frame](std::string* why) {
    const bool fixed = s.calibration_case == CalibrationCase::kFixedCamera;
    if (s.motion_preset) {
      s.motion = ThesisMotionPreset(*s.motion_preset, s.calibration_case);
      return true;
    }
    s.motion.frame = frame == MotionFrame::kWorld || (frame == MotionFrame::kAuto && fixed)
                         ? TwistProfile::Frame::kWorld
                         : TwistProfile::Frame::kBody;
    return s.motion.Check(why);
  });
}

void VisitMeasurements(FieldVisitor& v, ScenarioConfig& s) {
  VisitEnum(v,
            {"detections", "",
             "oracle: exact projections plus `noise`; rendered: frames rendered, detected with "
             "AprilTag 3, refined and matched (needs `aprilgrids`)."},
            &s.detections, DetectionsNames());
  v.Field({"sample_rate_hz", "Hz",
           "0: continuous measurements; > 0: frames at this rate, held between samples.", "≥ 0"},
          &s.measurements.sample_rate_hz);
  v.Field({"eval_rate_hz", "Hz",
           "Continuous sources: the frame grid the batch methods and the metrics use."},
          &s.measurements.eval_rate_hz);
  VisitEnum(v,
            {"outside_image", "",
             "Oracle: a projection outside `image_size` fails the trial (naming point, time and "
             "pixel), or is measured anyway (`keep`: the thesis's model)."},
            &s.outside_image, OutsideImageNames());
  v.Check(nullptr, [&s](std::string* why) {
    OracleOptions check = s.measurements;
    check.noise = NoiseOptions();
    return check.Check(why);
  });
}

const EnumNames<CalibrationChange::Kind>& ChangeKindNames() {
  static const EnumNames<CalibrationChange::Kind> names{
      {{CalibrationChange::Kind::kStep, "step"}, {CalibrationChange::Kind::kRamp, "ramp"}}};
  return names;
}

void VisitTruth(FieldVisitor& v, ScenarioConfig& s) {
  Visit(v, s.truth);
  ListOps changes;
  changes.size = s.truth_changes.size();
  changes.resize = [&s](size_t n) {
    s.truth_changes.resize(n);
    s.truth_change_marks.resize(n);
    s.truth_change_cameras.resize(n, -1);
  };
  changes.visit = [&s](size_t i, FieldVisitor& w) {
    Visit(w, s.truth_changes[i]);
    int whole_rig = -1;  // Changes added in code may have no entry: the whole rig.
    int& camera = i < s.truth_change_cameras.size() ? s.truth_change_cameras[i] : whole_rig;
    w.Field({"camera", "",
             "Rig scenarios: the camera the change moves, in the rig (rpy_deg about its own "
             "centre and the rig frame's axes, x_m in the rig frame) and its intrinsics; absent: "
             "the whole rig (the mount of camera 0 moves every camera with it; intrinsic deltas "
             "apply to every camera).",
             "≥ 0, < the rig's cameras", nullptr, camera < 0 ? kNotWritten : 0u},
            &camera);
  };
  changes.allow_empty = true;  // `changes: []` clears a base's.
  changes.located = [&s](size_t i, const std::string& where) { s.truth_change_marks[i] = where; };
  v.List({"changes", "",
          "Changes of the calibration over time, steps and ramps; their deltas add to the truth "
          "in list order. A change that changes nothing, non-finite deltas and times outside the "
          "run are refused.",
          "", nullptr, kOmitUnset},
         changes);
}

void VisitTolerance(FieldVisitor& v, TrackingOptions& t) {
  for (int q = 0; q < kTrackQuantities; ++q) {
    const char* name = TrackQuantityNames()[q];
    const bool angle = std::string(name).find("_deg") != std::string::npos;
    v.Field({name, angle ? "deg" : "px", "Re-convergence tolerance of this tracked quantity."},
            &t.tolerance[q]);
  }
}

}  // namespace

const EnumNames<Detections>& DetectionsNames() {
  static const EnumNames<Detections> names{
      {{Detections::kOracle, "oracle"}, {Detections::kRendered, "rendered"}}};
  return names;
}

const EnumNames<OutsideImage>& OutsideImageNames() {
  static const EnumNames<OutsideImage> names{
      {{OutsideImage::kFail, "fail"}, {OutsideImage::kKeep, "keep"}}};
  return names;
}

const EnumNames<PointsForm>& PointsFormNames() {
  static const EnumNames<PointsForm> names{{{PointsForm::kList, "list"},
                                            {PointsForm::kThesis, "thesis"},
                                            {PointsForm::kRandom, "random"},
                                            {PointsForm::kBoards, "boards"},
                                            {PointsForm::kAprilGrids, "aprilgrids"}}};
  return names;
}

const char* ToString(Detections d) { return DetectionsNames().Name(d); }

void Visit(FieldVisitor& v, ScenarioConfig& s) {
  v.Field({"name", "", "Keys the result rows (`scenario` column). Required.", "", nullptr,
           kNotSweepable},
          &s.name);
  v.Field({"description", "", "Free text."}, &s.description);
  VisitEnum(v,
            {"case", "",
             "Thesis calibration case: the camera rides a moving body (parent = body), or is fixed "
             "in the world and the points move."},
            &s.calibration_case, CaseNames());
  v.Field({"duration_s", "s", "Length of a trial.", "> 0, finite", PositiveFinite}, &s.duration_s);
  v.Field({"seed", "", "Base seed of every random draw."}, &s.seed);
  v.Field({"paired_sweep", "",
           "true: every sweep point runs the same trials (seeds), so rows pair trial by trial "
           "across points (diagnostics).",
           "", nullptr, kNotSweepable},
          &s.paired_sweep);
  v.Field({"trials", "", "Monte Carlo trials.", "≥ 1, ≤ 1000000",
           [](double n, std::string* why) {
             if (n < 1) return *why = "must be >= 1, got " + Integer(n), false;
             if (n > kMaxTrials) {
               *why = "at most " + std::to_string(kMaxTrials) + " per scenario (split the seeds)";
               return false;
             }
             return true;
           }},
          &s.trials);
  SectionOps truth;
  truth.visit = [&s](FieldVisitor& w) { VisitTruth(w, s); };
  v.Section({"truth", "", "The true camera at t = 0 and its changes over time."}, truth);
  v.Field({"image_size", "px",
           "[width, height] (at most 16384 px a side and 64 Mpx; zhang's initialisation, the "
           "image bound of oracle measurements, the rendered frames)."},
          &s.image_width, &s.image_height);
  v.Check("image_size", [&s](std::string* why) {
    if (s.image_width < 1 || s.image_height < 1) return *why = "must be positive", false;
    if (s.image_width > kMaxImageSide || s.image_height > kMaxImageSide ||
        static_cast<double>(s.image_width) * s.image_height > kMaxImagePixels) {
      *why = "[" + std::to_string(s.image_width) + ", " + std::to_string(s.image_height) +
             "] px is larger than any camera calibrated here (at most " +
             std::to_string(kMaxImageSide) + " px per side and " +
             std::to_string(static_cast<int>(kMaxImagePixels / 1e6)) +
             " Mpx; the renderer's ray table alone would need " +
             std::to_string(static_cast<long>(16.0 * (s.image_width + 1.0) *
                                              (s.image_height + 1.0) / (1 << 20))) +
             " MiB)";
      return false;
    }
    return true;
  });
  SectionOps rig;
  rig.visit = [&s](FieldVisitor& w) {
    ListOps cameras;
    cameras.size = s.rig.cameras.size();
    cameras.resize = [&s](size_t n) {
      s.rig.cameras.resize(n);
      s.rig.marks.resize(n);
    };
    cameras.visit = [&s](size_t i, FieldVisitor& x) { Visit(x, s.rig.cameras[i]); };
    cameras.flow_items = false;
    cameras.located = [&s](size_t i, const std::string& where) { s.rig.marks[i] = where; };
    w.List({"cameras", "",
            "The rig's cameras (at least 2), camera 0 first: the truth camera, whose entry has no "
            "intrinsics and the identity cam_from_rig."},
           cameras);
  };
  rig.reset = [&s] { s.rig = RigScenario(); };
  rig.written = s.rig.Any();
  v.Section({"rig", "",
             "A camera rig (camera/rig.h's conventions): every camera measures the same points at "
             "the same instants and every method runs on each camera; the rig's relative poses "
             "follow from two cameras' estimates. Replaces a base's section as a whole.",
             "", nullptr, kNotSweepable},
            rig);
  v.Field({"points", "",
           "The feature points: exactly one of `preset`, `list`, `random`, `boards`, "
           "`aprilgrids`. Replaces a base's section as a whole."},
          &s.points);
  SectionOps motion;
  motion.visit = [&s](FieldVisitor& w) { VisitMotion(w, s); };
  motion.reset = [&s] {
    s.motion = TwistProfile();
    s.motion_random_phase = false;
    s.motion_preset.reset();
  };
  v.Section({"motion", "",
             "The body (moving camera) or world (fixed camera) twist. Replaces a base's section as "
             "a whole."},
            motion);
  SectionOps measurements;
  measurements.visit = [&s](FieldVisitor& w) { VisitMeasurements(w, s); };
  v.Section({"measurements", "", "How the methods see the points."}, measurements);
  VisitSection(v, {"noise", "", "Noise of oracle measurements."}, &s.measurements.noise);
  VisitSection(v,
               {"rendering", "",
                "Renderer and detector of rendered measurements (`detections: rendered`); the "
                "frame rate is `measurements.sample_rate_hz`, the image size `image_size`."},
               &s.rendering);
  VisitSection(v,
               {"diagnostics", "",
                "Study-only decorators of the measurement source: where an error comes from "
                "(none by default)."},
               &s.diagnostics);
  v.Field({"methods", "",
           "The method instances, in row order: a list, or a map that updates the defaults "
           "([methods](#methods))."},
          &s.methods);
  VisitSection(v,
               {"tracking", "",
                "Estimates over time: recorded when the truth has `changes`, or when `enabled`."},
               &s.tracking);
  SectionOps reference;
  reference.visit = [&s](FieldVisitor& w) { Visit(w, s.reference); };
  reference.reset = [&s] { s.reference = Reference(); };
  reference.written = s.reference.Any() || !s.reference.source.empty();
  v.Section({"reference", "",
             "Published figures printed beside ours in `table.md` (all optional). Replaces a "
             "base's section as a whole."},
            reference);
  VisitSection(
      v,
      {"report", "", "Which question of the report the rows answer.", "", nullptr, kNotSweepable},
      &s.report, /*flow=*/true, /*written=*/s.report.role != ReportRole::kNone);
  VisitSection(
      v,
      {"sweep_point", "", "Written by calibench into `config.resolved.yaml`; not for users.", "",
       nullptr, kNotSweepable},
      &s.sweep_point, false, s.sweep_point.measurement_index >= 0);
}

void Visit(FieldVisitor& v, CameraSpec& c) {
  VisitSection(v, {"intrinsics", "", "The intrinsics."}, &c.intrinsics, /*flow=*/true);
  v.Field({"R_C", "",
           "Camera orientation in its parent frame (`parent_from_cam` rotation), a 3x3 list of "
           "rows; must be a rotation."},
          &c.r_c);
  v.Field({"x_C", "m", "Camera position in its parent frame."}, &c.x_c);
  v.Field({"allow_improper_rotation", "",
           "Accept det(R_C) = -1 (to reproduce a source that printed such a matrix)."},
          &c.allow_improper_rotation);
  v.Check("R_C", [&c](std::string* why) {
    return CheckRotation(c.r_c, 1e-9, c.allow_improper_rotation, why);
  });
}

void Visit(FieldVisitor& v, CameraIntrinsics& k) {
  v.Refused("k5",
            "no lens model has k5: the equidistant (fisheye, Kannala-Brandt) model has k1..k4, as "
            "OpenCV's cv::fisheye and Kalibr's equidistant; radtan has k1 k2 p1 p2 k3");
  v.Field({"fku_px", "px", "f·ku, focal length in horizontal pixels."}, &k.fku_px);
  v.Field({"fkv_px", "px", "f·kv, focal length in vertical pixels."}, &k.fkv_px);
  v.Field({"phi_deg", "deg", "Angle between the sensor axes (90: no skew).", "in (0, 180)"},
          &k.phi_deg);
  v.Field({"u0_px", "px", "Principal point, horizontal (pixel-centre convention)."}, &k.u0_px);
  v.Field({"v0_px", "px", "Principal point, vertical."}, &k.v0_px);
  v.Field({"k1", "", "Radial term (radtan: of r²; equidistant: of θ²)."}, &k.k1);
  v.Field({"k2", "", "Radial term (radtan: of r⁴; equidistant: of θ⁴)."}, &k.k2);
  v.Field({"p1", "", "Tangential term (radtan only)."}, &k.p1);
  v.Field({"p2", "", "Tangential term (radtan only)."}, &k.p2);
  v.Field({"k3", "", "radtan: r⁶; equidistant: θ⁶."}, &k.k3);
  v.Field({"k4", "", "equidistant only: θ⁸.", "", nullptr, kOmitUnset}, &k.k4);
  VisitEnum(v,
            {"lens_family", "",
             "The projection and how k1..k4, ξ, α and β are read "
             "([camera-models.md](camera-models.md)).",
             "", nullptr, kOmitUnset},
            &k.family, ScenarioLensFamilies());
  v.Field({"xi", "", "unified (≥ 0) and double-sphere (> -1): the (first) sphere's offset ξ.", "",
           nullptr, kOmitUnset},
          &k.xi);
  v.Field({"alpha", "", "eucm and double-sphere: the weight α of the last projection.", "in [0, 1]",
           nullptr, kOmitUnset},
          &k.alpha);
  // Written for the families that have it only (its default 1 is the sphere), so that other
  // families' files stay short.
  const auto& lens = InfoOf(k.family).lens_params;
  const bool has_beta =
      std::any_of(lens.begin(), lens.end(), [](const char* n) { return std::string(n) == "beta"; });
  v.Field({"beta", "", "eucm only: the ellipsoid's shape β (1: a sphere).", "> 0", nullptr,
           has_beta ? 0u : kNotWritten},
          &k.beta);
  v.Check(nullptr, [&k](std::string* why) { return k.Check(why); });
}

void Visit(FieldVisitor& v, CalibrationChange& c) {
  VisitEnum(v,
            {"kind", "", "A step at `at_s`, or a ramp reached linearly from `from_s` to `to_s`.",
             "", nullptr, kRequired},
            &c.kind, ChangeKindNames());
  // A step is written with at_s, a ramp with from_s and to_s (CalibrationChange holds both times).
  const bool step = c.kind == CalibrationChange::Kind::kStep;
  const double unset = std::numeric_limits<double>::quiet_NaN();
  double at_s = v.Reads() || !step ? unset : c.from_s;
  double from_s = v.Reads() || step ? unset : c.from_s;
  double to_s = v.Reads() || step ? unset : c.to_s;
  v.Field({"at_s", "s", "A step's time, inside [0, duration_s] (a step needs it).", "", nullptr,
           kOmitUnset},
          &at_s);
  v.Field({"from_s", "s", "A ramp's start, inside [0, duration_s] (a ramp needs it).", "", nullptr,
           kOmitUnset},
          &from_s);
  v.Field(
      {"to_s", "s", "A ramp's end (a ramp needs it). Two ramps of one quantity may not overlap.",
       "", nullptr, kOmitUnset},
      &to_s);
  v.Exclusive("at_s", {"from_s", "to_s"},
              "a step has `at_s`, a ramp (`kind: ramp`) `from_s` and `to_s`");
  const auto given = [](double t) {
    return [t](std::string* why) {
      return !std::isnan(t) || (*why = "missing (or not a number)", false);
    };
  };
  if (step) {
    v.Check("at_s", given(at_s));
  } else {
    v.Check("from_s", given(from_s));
    v.Check("to_s", given(to_s));
  }
  if (v.Reads()) {
    c.from_s = step ? at_s : from_s;
    c.to_s = step ? at_s : to_s;
  }
  v.Field({"rpy_deg", "deg",
           "Mount rotation: parent_from_cam ← R(rpy)·parent_from_cam, about the parent's z, y, x "
           "axes ([roll, pitch, yaw])."},
          &c.rpy_deg);
  v.Field({"x_m", "m", "Shift of x_C in the parent frame."}, &c.x_m);
  v.Field({"fku_px", "px", "Added to f·ku."}, &c.fku_px);
  v.Field({"fkv_px", "px", "Added to f·kv."}, &c.fkv_px);
  v.Field({"u0_px", "px", "Added to u0."}, &c.u0_px);
  v.Field({"v0_px", "px", "Added to v0."}, &c.v0_px);
  v.Field({"phi_deg", "deg", "Added to φ."}, &c.phi_deg);
  // Changing nothing and non-finite values are refused here; the times against the scenario's
  // duration once it is known (the configuration's loader).
  v.Check(nullptr,
          [&c](std::string* why) { return c.Check(std::numeric_limits<double>::infinity(), why); });
}

void Visit(FieldVisitor& v, TrackingConfig& t) {
  v.Field({"enabled", "", "Record tracks without truth changes too."}, &t.enabled);
  v.Field({"report_rate_hz", "Hz", "Report times: 0 = every frame; else k / rate.", "≥ 0"},
          &t.report_rate_hz);
  v.Field(
      {"band_samples", "",
       "At most this many report times per trial in track_errors.csv / track_bands.csv.", "≥ 2"},
      &t.band_samples);
  v.Field({"steady_fraction", "", "The last part of each segment that `steady_err` is taken over."},
          &t.metrics.steady_fraction);
  SectionOps tolerance;
  tolerance.visit = [&t](FieldVisitor& w) { VisitTolerance(w, t.metrics); };
  tolerance.flow = true;
  v.Section({"tolerance", "", "Re-convergence tolerance per tracked quantity."}, tolerance);
  v.Check(nullptr, [&t](std::string* why) { return t.Check(why); });
}

void Visit(FieldVisitor& v, Reference& r) {
  v.Field({"source", "", "e.g. \"thesis sim 7\"."}, &r.source);
  v.Field({"method", "", "The instance it describes (default: the first enabled one).", "", nullptr,
           kOmitUnset},
          &r.method);
  v.Field({"fku_px", "px", "Published f·ku.", "", nullptr, kOmitUnset}, &r.fku_px);
  v.Field({"fkv_px", "px", "Published f·kv.", "", nullptr, kOmitUnset}, &r.fkv_px);
  v.Field({"phi_deg", "deg", "Published φ.", "", nullptr, kOmitUnset}, &r.phi_deg);
  v.Field({"u0_px", "px", "Published u0.", "", nullptr, kOmitUnset}, &r.u0_px);
  v.Field({"v0_px", "px", "Published v0.", "", nullptr, kOmitUnset}, &r.v0_px);
  v.Field({"theta_err_below", "", "\"exact\": the source reports ‖θ̃‖ below this.", "", nullptr,
           kOmitUnset},
          &r.theta_err_below);
  v.Field({"x_C", "m", "Published camera position.", "", nullptr, kOmitUnset}, &r.x_c);
}

void Visit(FieldVisitor& v, ReportConfig& r) {
  VisitEnum(v,
            {"role", "",
             "The report question these rows answer (written to schema.json; the report never "
             "matches sweep names).",
             "", nullptr, kOmitUnset},
            &r.role, ReportRoleNames());
}

void Visit(FieldVisitor& v, SweepPoint& p) {
  v.Field({"sweep", "", "The swept scenario's name."}, &p.sweep);
  v.Field({"index", "", "Position in the sweep's product."}, &p.index);
  v.Field({"measurement_index", "", "Position among the measurement points."},
          &p.measurement_index);
  v.Field({"params", "", "field=value;... of the point."}, &p.params);
}

void Visit(FieldVisitor& v, PlacedBoard& b) {
  v.Field({"rows", "", "Corners per column."}, &b.board.rows);
  v.Field({"cols", "", "Corners per row."}, &b.board.cols);
  v.Field({"spacing_m", "m", "Corner pitch."}, &b.board.spacing_m);
  v.Field({"origin", "m", "Board origin in the points frame."},
          &b.board.points_from_board.translation);
  v.Field({"rpy_deg", "deg", "Board orientation in the points frame (roll, pitch, yaw)."},
          &b.rpy_deg);
  v.Check(nullptr, [&b](std::string* why) {
    b.board.points_from_board.rotation = FromRollPitchYawDeg(b.rpy_deg);
    return b.board.Check(why);
  });
}

void Visit(FieldVisitor& v, PlacedAprilGrid& p) {
  AprilGrid& g = p.grid;
  v.Field({"family", "", "AprilTag family."}, &g.family, Choices{TagFamily::Names()});
  v.Field({"tag_rows", "", "Tags per column."}, &g.tag_rows);
  v.Field({"tag_cols", "", "Tags per row."}, &g.tag_cols);
  v.Field({"tag_size_m", "m", "Edge of a tag's black square, border included (Kalibr's tagSize)."},
          &g.tag_size_m);
  v.Field(
      {"tag_spacing", "", "Gap between tags as a fraction of `tag_size_m` (Kalibr's tagSpacing)."},
      &g.tag_spacing);
  v.Field({"first_id", "", "Id of the bottom-left tag (Kalibr's codeOffset)."}, &g.first_id);
  v.Field(
      {"black_tag_border", "bits", "1: AprilTag 3's layout; 2: Kalibr's printed grids.", "1 or 2"},
      &g.black_tag_border);
  v.Field({"corner_squares", "", "Kalibr's black squares at the tag corners."}, &g.corner_squares);
  v.Field({"origin", "m", "Grid origin in the points frame."}, &g.points_from_board.translation);
  v.Field({"rpy_deg", "deg", "Grid orientation in the points frame (roll, pitch, yaw)."},
          &p.rpy_deg);
  v.Check(nullptr, [&p](std::string* why) {
    p.grid.points_from_board.rotation = FromRollPitchYawDeg(p.rpy_deg);
    return p.grid.Check(why);
  });
}

void Visit(FieldVisitor& v, PointsConfig& p) {
  std::string preset = "thesis";
  v.Field({"preset", "", "The thesis's feature points."}, &preset, Choices{{"thesis"}});
  v.Field({"count", "", "With `preset`: how many of them (the first ones).", "1 to 10"}, &p.count);
  v.Field({"list", "m",
           "Explicit [x, y, z] points (in the points frame: world for a moving camera, body for "
           "a fixed one)."},
          &p.xyz);
  SectionOps random;
  random.visit = [&p](FieldVisitor& w) { VisitRandomBox(w, p); };
  random.flow = true;
  v.Section({"random", "",
             "Points uniform in the box [min, max], drawn once from the scenario "
             "seed. All three keys required."},
            random);
  VisitList(v,
            {"boards", "", "Planar chessboard-like boards (a rig); their corners are the points."},
            &p.boards);
  VisitList(v,
            {"aprilgrids", "",
             "Kalibr AprilGrids (needed for `detections: rendered`); their tag corners are the "
             "points."},
            &p.aprilgrids);
}

void VisitRandomBox(FieldVisitor& v, PointsConfig& p) {
  static_assert(kMaxScenarioPoints == 100000, "the count's constraint below says it");
  v.Field({"count", "", "How many points.", "1 to 100000"}, &p.count);
  v.Field({"min", "m", "Lower corner of the box."}, &p.random_min);
  v.Field({"max", "m", "Upper corner of the box."}, &p.random_max);
}

std::vector<std::string> SweepableKeys() {
  class Keys final : public SpecVisitor {
   public:
    std::vector<std::string> keys;
    void Spec(const FieldSpec& f) override {
      if (!(f.flags & kNotSweepable)) keys.emplace_back(f.key);
    }
  } keys;
  ScenarioConfig s;
  Visit(keys, s);
  return keys.keys;
}

}  // namespace calibench
