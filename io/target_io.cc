// Config I/O for AprilTag targets and rendering (scenario sections and Kalibr target files).
#include "io/target_io.h"

#include <cmath>
#include <cstdlib>
#include <string>
#include <utility>

#include "io/yaml_reader.h"
#include "sim/tag_family.h"
#include "util/format.h"

namespace calibench {

namespace {

// The shortest of 15 and 17 significant digits that reads back to v: 0.088, not
// 0.087999999999999995, yet every double round-trips.
std::string RoundTripNumber(double v) {
  const std::string short_text = FormatNumber(v, 15);
  return std::strtod(short_text.c_str(), nullptr) == v ? short_text : FormatNumber(v, 17);
}

}  // namespace

std::string TargetYamlText(const CalibrationTarget& t) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  if (t.type == CalibrationTarget::Type::kAprilGrid) {
    out << YAML::Key << "target_type" << YAML::Value << "aprilgrid" << YAML::Key << "tagCols"
        << YAML::Value << t.grid.tag_cols << YAML::Key << "tagRows" << YAML::Value
        << t.grid.tag_rows << YAML::Key << "tagSize" << YAML::Value
        << RoundTripNumber(t.grid.tag_size_m) << YAML::Key << "tagSpacing" << YAML::Value
        << RoundTripNumber(t.grid.tag_spacing) << YAML::Key << "blackTagBorder" << YAML::Value
        << t.grid.black_tag_border << YAML::Key << "tagFamily" << YAML::Value << t.grid.family
        << YAML::Key << "codeOffset" << YAML::Value << t.grid.first_id << YAML::Key
        << "cornerSquares" << YAML::Value << t.grid.corner_squares;
  } else {
    out << YAML::Key << "target_type" << YAML::Value << "checkerboard" << YAML::Key << "targetCols"
        << YAML::Value << t.cols << YAML::Key << "targetRows" << YAML::Value << t.rows << YAML::Key
        << "rowSpacingMeters" << YAML::Value << RoundTripNumber(t.row_spacing_m) << YAML::Key
        << "colSpacingMeters" << YAML::Value << RoundTripNumber(t.col_spacing_m);
  }
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

bool LoadTargetYaml(const std::string& path, CalibrationTarget* target, std::string* why) {
  std::string text;
  const bool read = config_internal::CatchConfigErrors(
      path, why, [&] { text = config_internal::ReadFile(path); });
  return read && LoadTargetYamlFromString(text, path, target, why);
}

bool LoadTargetYamlFromString(const std::string& yaml, const std::string& path,
                              CalibrationTarget* target, std::string* why) {
  using config_internal::Reader;
  return config_internal::CatchConfigErrors(path, why, [&] {
    const YAML::Node root = config_internal::LoadYaml(yaml, path);
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
                   "codeOffset", "blackTagBorder", "cornerSquares"});
      t.type = CalibrationTarget::Type::kAprilGrid;
      t.grid.tag_cols = r.Int(required("tagCols"), "tagCols");
      t.grid.tag_rows = r.Int(required("tagRows"), "tagRows");
      t.grid.tag_size_m = r.Double(required("tagSize"), "tagSize");
      t.grid.tag_spacing = r.Double(required("tagSpacing"), "tagSpacing");
      r.If(root, "tagFamily", "",
           [&](auto n, auto f) { t.grid.family = r.Choice(n, f, TagFamily::Names()); });
      r.If(root, "codeOffset", "", [&](auto n, auto f) { t.grid.first_id = r.Int(n, f); });
      // Kalibr's default (its detector option blackTagBorder) where the family's border is black;
      // the reversed-border families have only AprilTag 3's own 1-bit layout.
      t.grid.black_tag_border = CheckBorderBits(t.grid.family, 2, nullptr) ? 2 : 1;
      r.If(root, "blackTagBorder", "",
           [&](auto n, auto f) { t.grid.black_tag_border = r.Int(n, f); });
      t.grid.corner_squares = true;  // Every Kalibr grid has them.
      r.If(root, "cornerSquares", "",
           [&](auto n, auto f) { t.grid.corner_squares = r.Bool(n, f); });
      // Each field's own reason, named (AprilGrid::Check would say it in its own words).
      if (t.grid.tag_cols < 1) r.Fail(root["tagCols"], "tagCols", "must be >= 1");
      if (t.grid.tag_rows < 1) r.Fail(root["tagRows"], "tagRows", "must be >= 1");
      if (!(t.grid.tag_size_m > 0 && std::isfinite(t.grid.tag_size_m))) {
        r.Fail(root["tagSize"], "tagSize",
               "must be > 0 (the edge of a tag's black square, border included, in metres)");
      }
      if (!(t.grid.tag_spacing > 0 && std::isfinite(t.grid.tag_spacing))) {
        r.Fail(root["tagSpacing"], "tagSpacing",
               "must be > 0 (the gap between tags as a fraction of tagSize, e.g. 0.3)");
      }
      if (t.grid.black_tag_border != 1 && t.grid.black_tag_border != 2) {
        r.Fail(root["blackTagBorder"], "blackTagBorder",
               "must be 1 (AprilTag 3's layout) or 2 (Kalibr's printed grids, the default); "
               "Kalibr's detector and target generator use no other width");
      }
      std::string reason;
      if (!CheckBorderBits(t.grid.family, t.grid.black_tag_border, &reason)) {
        r.Fail(root["blackTagBorder"], "blackTagBorder", reason);
      }
      if (t.grid.first_id < 0) r.Fail(root["codeOffset"], "codeOffset", "must be >= 0");
      // What Check can still refuse: ids past the family's codes (tagRows x tagCols tags from
      // codeOffset, in tagFamily).
      if (!t.grid.Check(&reason)) r.Fail(root["tagRows"], "tagRows x tagCols", reason);
    } else {
      r.CheckKeys(
          root, "",
          {"target_type", "targetCols", "targetRows", "rowSpacingMeters", "colSpacingMeters"});
      t.type = CalibrationTarget::Type::kCheckerboard;
      t.cols = r.Int(required("targetCols"), "targetCols");
      t.rows = r.Int(required("targetRows"), "targetRows");
      t.row_spacing_m = r.Double(required("rowSpacingMeters"), "rowSpacingMeters");
      t.col_spacing_m = r.Double(required("colSpacingMeters"), "colSpacingMeters");
      if (t.cols < 2 || t.rows < 2) {
        r.Fail(root, "targetCols", "a checkerboard needs at least 2 x 2 inner corners");
      }
      for (const auto& [key, n] : {std::pair<const char*, int>{"targetCols", t.cols},
                                   std::pair<const char*, int>{"targetRows", t.rows}}) {
        if (n > kMaxCornersPerSide) {
          r.Fail(root[key], key,
                 "at most " + std::to_string(kMaxCornersPerSide) + " inner corners a side");
        }
      }
      if (!(t.row_spacing_m > 0) || !(t.col_spacing_m > 0)) {
        r.Fail(root, "rowSpacingMeters", "spacings must be > 0");
      }
    }
    *target = t;
  });
}

}  // namespace calibench
