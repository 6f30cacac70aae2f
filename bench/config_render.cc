// Config I/O for AprilTag targets and rendering (scenario sections and Kalibr target files).
#include "bench/config_parsers.h"
#include "bench/target_io.h"
#include "core/tag_family.h"

namespace calibench {
namespace config_internal {

void ParseAprilGrid(const Reader& r, const YAML::Node& node, const std::string& field,
                    AprilGrid* g) {
  r.CheckKeys(node, field,
              {"family", "tag_rows", "tag_cols", "tag_size_m", "tag_spacing", "first_id", "origin",
               "rpy_deg"});
  r.If(node, "family", field,
       [&](auto n, auto f) { g->family = r.Choice(n, f, TagFamily::Names()); });
  r.If(node, "tag_rows", field,
       [&](auto n, auto f) { g->tag_rows = static_cast<int>(r.Integer(n, f)); });
  r.If(node, "tag_cols", field,
       [&](auto n, auto f) { g->tag_cols = static_cast<int>(r.Integer(n, f)); });
  r.If(node, "tag_size_m", field, [&](auto n, auto f) { g->tag_size_m = r.Double(n, f); });
  r.If(node, "tag_spacing", field, [&](auto n, auto f) { g->tag_spacing = r.Double(n, f); });
  r.If(node, "first_id", field,
       [&](auto n, auto f) { g->first_id = static_cast<int>(r.Integer(n, f)); });
  r.If(node, "origin", field,
       [&](auto n, auto f) { g->points_from_board.translation = r.Vector3(n, f); });
  r.If(node, "rpy_deg", field, [&](auto n, auto f) {
    g->points_from_board.rotation = FromRollPitchYawDeg(r.Vector3(n, f));
  });
  std::string why;
  if (!g->Check(&why)) r.Fail(node, field, why);
}

void ParseRendering(const Reader& r, const YAML::Node& node, const std::string& field,
                    RenderedSourceOptions* o) {
  r.CheckKeys(node, field,
              {"supersample", "blur_sigma_px", "noise_sigma_gray", "background_gray", "black_gray",
               "white_gray", "threads", "refine_corners", "detector"});
  RenderOptions& ro = o->render;
  r.If(node, "supersample", field,
       [&](auto n, auto f) { ro.supersample = static_cast<int>(r.Integer(n, f)); });
  r.If(node, "blur_sigma_px", field, [&](auto n, auto f) { ro.blur_sigma_px = r.Double(n, f); });
  r.If(node, "noise_sigma_gray", field,
       [&](auto n, auto f) { ro.noise_sigma_gray = r.Double(n, f); });
  r.If(node, "background_gray", field,
       [&](auto n, auto f) { ro.background_gray = r.Double(n, f); });
  r.If(node, "black_gray", field, [&](auto n, auto f) { ro.black_gray = r.Double(n, f); });
  r.If(node, "white_gray", field, [&](auto n, auto f) { ro.white_gray = r.Double(n, f); });
  r.If(node, "threads", field,
       [&](auto n, auto f) { o->threads = static_cast<int>(r.Integer(n, f)); });
  r.If(node, "refine_corners", field,
       [&](auto n, auto f) { o->detection.refine_corners = r.Bool(n, f); });
  r.If(node, "detector", field, [&](const YAML::Node& d, const std::string& df) {
    r.CheckKeys(d, df,
                {"quad_decimate", "quad_sigma", "refine_edges", "decode_sharpening", "threads",
                 "max_hamming"});
    AprilTagOptions& a = o->detection.detector;
    r.If(d, "quad_decimate", df, [&](auto n, auto f) { a.quad_decimate = r.Double(n, f); });
    r.If(d, "quad_sigma", df, [&](auto n, auto f) { a.quad_sigma = r.Double(n, f); });
    r.If(d, "refine_edges", df, [&](auto n, auto f) { a.refine_edges = r.Bool(n, f); });
    r.If(d, "decode_sharpening", df, [&](auto n, auto f) { a.decode_sharpening = r.Double(n, f); });
    r.If(d, "threads", df, [&](auto n, auto f) { a.threads = static_cast<int>(r.Integer(n, f)); });
    r.If(d, "max_hamming", df,
         [&](auto n, auto f) { a.max_hamming = static_cast<int>(r.Integer(n, f)); });
    std::string why;
    if (!a.Check(&why)) r.Fail(d, df, why);
  });
  std::string why;
  if (o->threads < 0) r.Fail(node, Reader::Join(field, "threads"), "must be >= 0 (0: all cores)");
  RenderOptions check = ro;
  if (!check.Check(&why)) r.Fail(node, field, why);
}

namespace {

void EmitVector(YAML::Emitter& out, const Eigen::Vector3d& v) {
  out << YAML::Flow << YAML::BeginSeq << v[0] << v[1] << v[2] << YAML::EndSeq;
}

}  // namespace

void EmitAprilGrid(YAML::Emitter& out, const AprilGrid& g) {
  out << YAML::Flow << YAML::BeginMap << YAML::Key << "family" << YAML::Value << g.family
      << YAML::Key << "tag_rows" << YAML::Value << g.tag_rows << YAML::Key << "tag_cols"
      << YAML::Value << g.tag_cols << YAML::Key << "tag_size_m" << YAML::Value << g.tag_size_m
      << YAML::Key << "tag_spacing" << YAML::Value << g.tag_spacing << YAML::Key << "first_id"
      << YAML::Value << g.first_id << YAML::Key << "origin" << YAML::Value;
  EmitVector(out, g.points_from_board.translation);
  out << YAML::Key << "rpy_deg" << YAML::Value;
  EmitVector(out, RollPitchYawDeg(g.points_from_board.rotation));
  out << YAML::EndMap;
}

void EmitRendering(YAML::Emitter& out, const RenderedSourceOptions& o) {
  const RenderOptions& ro = o.render;
  const AprilTagOptions& a = o.detection.detector;
  out << YAML::BeginMap << YAML::Key << "supersample" << YAML::Value << ro.supersample << YAML::Key
      << "blur_sigma_px" << YAML::Value << ro.blur_sigma_px << YAML::Key << "noise_sigma_gray"
      << YAML::Value << ro.noise_sigma_gray << YAML::Key << "background_gray" << YAML::Value
      << ro.background_gray << YAML::Key << "black_gray" << YAML::Value << ro.black_gray
      << YAML::Key << "white_gray" << YAML::Value << ro.white_gray << YAML::Key << "threads"
      << YAML::Value << o.threads << YAML::Key << "refine_corners" << YAML::Value
      << o.detection.refine_corners << YAML::Key << "detector" << YAML::Value << YAML::Flow
      << YAML::BeginMap << YAML::Key << "quad_decimate" << YAML::Value << a.quad_decimate
      << YAML::Key << "quad_sigma" << YAML::Value << a.quad_sigma << YAML::Key << "refine_edges"
      << YAML::Value << a.refine_edges << YAML::Key << "decode_sharpening" << YAML::Value
      << a.decode_sharpening << YAML::Key << "threads" << YAML::Value << a.threads << YAML::Key
      << "max_hamming" << YAML::Value << a.max_hamming << YAML::EndMap << YAML::EndMap;
}

}  // namespace config_internal

bool LoadTargetYaml(const std::string& path, CalibrationTarget* target, std::string* why) {
  using config_internal::Reader;
  return config_internal::CatchConfigErrors(path, why, [&] {
    const YAML::Node root = config_internal::LoadYaml(config_internal::ReadFile(path), path);
    const Reader r(path);
    r.ExpectMap(root, "(top level)");
    if (!root["target_type"].IsDefined()) r.Fail(root, "target_type", "missing");
    const std::string type =
        r.Choice(root["target_type"], "target_type", {"aprilgrid", "checkerboard"});
    CalibrationTarget t;
    auto required = [&](const char* key) {
      if (!root[key].IsDefined()) r.Fail(root, key, "missing (needed by a " + type + ")");
      return root[key];
    };
    if (type == "aprilgrid") {
      r.CheckKeys(root, "",
                  {"target_type", "tagCols", "tagRows", "tagSize", "tagSpacing", "tagFamily",
                   "codeOffset"});
      t.type = CalibrationTarget::Type::kAprilGrid;
      t.grid.tag_cols = static_cast<int>(r.Integer(required("tagCols"), "tagCols"));
      t.grid.tag_rows = static_cast<int>(r.Integer(required("tagRows"), "tagRows"));
      t.grid.tag_size_m = r.Double(required("tagSize"), "tagSize");
      t.grid.tag_spacing = r.Double(required("tagSpacing"), "tagSpacing");
      r.If(root, "tagFamily", "",
           [&](auto n, auto f) { t.grid.family = r.Choice(n, f, TagFamily::Names()); });
      r.If(root, "codeOffset", "",
           [&](auto n, auto f) { t.grid.first_id = static_cast<int>(r.Integer(n, f)); });
      std::string reason;
      if (!t.grid.Check(&reason)) r.Fail(root, "(target)", reason);
    } else {
      r.CheckKeys(
          root, "",
          {"target_type", "targetCols", "targetRows", "rowSpacingMeters", "colSpacingMeters"});
      t.type = CalibrationTarget::Type::kCheckerboard;
      t.cols = static_cast<int>(r.Integer(required("targetCols"), "targetCols"));
      t.rows = static_cast<int>(r.Integer(required("targetRows"), "targetRows"));
      t.row_spacing_m = r.Double(required("rowSpacingMeters"), "rowSpacingMeters");
      t.col_spacing_m = r.Double(required("colSpacingMeters"), "colSpacingMeters");
      if (t.cols < 2 || t.rows < 2) {
        r.Fail(root, "targetCols", "a checkerboard needs at least 2 x 2 inner corners");
      }
      if (!(t.row_spacing_m > 0) || !(t.col_spacing_m > 0)) {
        r.Fail(root, "rowSpacingMeters", "spacings must be > 0");
      }
    }
    *target = t;
  });
}

}  // namespace calibench
