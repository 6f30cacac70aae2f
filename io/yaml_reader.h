// YAML access that names the file, line, column and dotted field in every error: the private
// helper of config_io.cc (part of the config I/O, the only yaml-cpp users).
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace calibench {
namespace config_internal {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  // "where: field: reason" (Reader::Fail), with its parts kept: where (file or file:line:col), the
  // dotted field, the reason.
  ConfigError(const std::string& where, const std::string& field, const std::string& reason)
      : std::runtime_error(where + ": " + field + ": " + reason),
        where_(where),
        field_(field),
        reason_(reason) {}
  // Empty for an error made from one message.
  const std::string& where() const { return where_; }
  const std::string& field() const { return field_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string where_, field_, reason_;
};

// The text of a file; ConfigError naming it when it cannot be opened.
// A configuration is a small text file: a device, a FIFO or a directory (e.g. `base: /dev/zero`)
// would hang or mislead the parser, so only regular files up to kMaxConfigBytes are read.
constexpr std::uintmax_t kMaxConfigBytes = 16u << 20;

inline std::string ReadFile(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) {
    throw ConfigError(path + ": (file): cannot open for reading: no such file");
  }
  if (!std::filesystem::is_regular_file(status)) {
    throw ConfigError(path + ": (file): not a regular file");
  }
  if (std::filesystem::file_size(path, ec) > kMaxConfigBytes) {
    throw ConfigError(path + ": (file): larger than 16 MiB; not a configuration");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path + ": (file): cannot open for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Parsed YAML; ConfigError with file, line and column when it is malformed.
inline YAML::Node LoadYaml(const std::string& text, const std::string& path) {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    std::ostringstream msg;
    msg << path << ":" << e.mark.line + 1 << ":" << e.mark.column + 1
        << ": (yaml): malformed YAML: " << e.msg;
    throw ConfigError(msg.str());
  }
}

// Runs `body`; a ConfigError or a yaml-cpp exception becomes false and *why (naming `path`).
template <typename Body>
bool CatchConfigErrors(const std::string& path, std::string* why, const Body& body) {
  try {
    body();
    return true;
  } catch (const ConfigError& e) {
    if (why) *why = e.what();
  } catch (const YAML::Exception& e) {
    if (why) *why = path + ": (yaml): " + e.what();
  }
  return false;
}

inline size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// The name of `names` closest to a misspelt `value` (edit distance at most 2), or "": the
// "did you mean" of a message.
inline std::string ClosestName(const std::string& value, const std::vector<std::string>& names) {
  std::string best;
  size_t best_distance = 3;
  for (const std::string& n : names) {
    const size_t d = EditDistance(value, n);
    if (d < best_distance) best_distance = d, best = n;
  }
  return best;
}

// The refusal of `value` outside the closed set `names`: "'x' is not one of: a, b", or with a
// `noun` "unknown <noun> 'x' (one of: a, b)"; then the "did you mean" of ClosestName.
inline std::string NotOneOf(const std::string& value, const std::vector<std::string>& names,
                            const std::string& noun = "") {
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  std::string reason = noun.empty() ? "'" + value + "' is not one of: " + list
                                    : "unknown " + noun + " '" + value + "' (one of: " + list + ")";
  const std::string best = ClosestName(value, names);
  if (!best.empty()) reason += " (did you mean '" + best + "'?)";
  return reason;
}

// Parses one file's nodes, naming the file and the dotted field path in every error.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  // "file:line:col" of `node` (1-based), or the file alone for a node built in memory.
  std::string Where(const YAML::Node& node) const {
    std::ostringstream where;
    where << file_;
    if (node.IsDefined() && node.Mark().line >= 0) {
      where << ":" << node.Mark().line + 1 << ":" << node.Mark().column + 1;
    }
    return where.str();
  }

  [[noreturn]] void Fail(const YAML::Node& node, const std::string& field,
                         const std::string& reason) const {
    throw ConfigError(Where(node), field, reason);
  }

  void ExpectMap(const YAML::Node& node, const std::string& field) const {
    if (!node.IsMap()) Fail(node, field, "expected a mapping of keys to values");
  }

  // Every key of `node` must be in `allowed`; suggests the closest for a misspelt one.
  void CheckKeys(const YAML::Node& node, const std::string& field,
                 const std::vector<std::string>& allowed) const {
    ExpectMap(node, field);
    for (const auto& kv : node) {
      const std::string key = kv.first.Scalar();
      if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      std::string best;
      size_t best_distance = 3;
      for (const std::string& a : allowed) {
        // A dropped unit suffix (pixel_sigma for pixel_sigma_px) counts as a near miss too.
        const bool prefix = key.size() >= 4 && a.compare(0, key.size(), key) == 0;
        const size_t d = prefix ? 1 : EditDistance(key, a);
        if (d < best_distance) best_distance = d, best = a;
      }
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      std::string reason = "unknown key";
      if (!best.empty()) reason += " (did you mean '" + best + "'?)";
      reason += "; allowed: ";
      reason += list;
      Fail(kv.first, Join(field, key), reason);
    }
  }

  static std::string Join(const std::string& field, const std::string& key) {
    return field.empty() ? key : field + "." + key;
  }

  // A scalar converted to T; `expected` names the type in the error ("a number").
  template <typename T>
  T Scalar(const YAML::Node& node, const std::string& field, const std::string& expected) const {
    if (!node.IsScalar()) Fail(node, field, "expected " + expected);
    try {
      return node.as<T>();
    } catch (const YAML::Exception&) {
      Fail(node, field, "expected " + expected + ", got '" + node.Scalar() + "'");
    }
  }
  double Double(const YAML::Node& node, const std::string& field) const {
    return Scalar<double>(node, field, "a number");
  }
  long Integer(const YAML::Node& node, const std::string& field) const {
    return Scalar<long>(node, field, "an integer");
  }
  // An integer that fits an int (a long parsed, then range-checked: never wraps).
  int Int(const YAML::Node& node, const std::string& field) const {
    const long value = Integer(node, field);
    if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
      Fail(node, field, "integer " + node.Scalar() + " out of range");
    }
    return static_cast<int>(value);
  }
  uint64_t Unsigned(const YAML::Node& node, const std::string& field) const {
    // yaml-cpp wraps "-1" to a huge unsigned value: refuse a sign outright.
    if (node.IsScalar() && node.Scalar().find('-') != std::string::npos) {
      Fail(node, field, "expected a non-negative integer, got '" + node.Scalar() + "'");
    }
    return Scalar<uint64_t>(node, field, "a non-negative integer");
  }
  bool Bool(const YAML::Node& node, const std::string& field) const {
    return Scalar<bool>(node, field, "true or false");
  }
  std::string String(const YAML::Node& node, const std::string& field) const {
    if (!node.IsScalar()) Fail(node, field, "expected a string");
    return node.Scalar();
  }
  std::string Choice(const YAML::Node& node, const std::string& field,
                     const std::vector<std::string>& choices) const {
    std::string value = String(node, field);
    if (std::find(choices.begin(), choices.end(), value) != choices.end()) return value;
    Fail(node, field, NotOneOf(value, choices));
  }
  Eigen::Vector3d Vector3(const YAML::Node& node, const std::string& field) const {
    if (!node.IsSequence() || node.size() != 3) Fail(node, field, "expected a list of 3 numbers");
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v[i] = Double(node[i], field + "[" + std::to_string(i) + "]");
    return v;
  }
  Eigen::Matrix3d Matrix3(const YAML::Node& node, const std::string& field) const {
    if (!node.IsSequence() || node.size() != 3) {
      Fail(node, field, "expected a 3x3 matrix as a list of 3 rows");
    }
    Eigen::Matrix3d m;
    for (int r = 0; r < 3; ++r) {
      m.row(r) = Vector3(node[r], field + "[" + std::to_string(r) + "]").transpose();
    }
    return m;
  }

  // Calls `apply` when `key` is present in the map `node`.
  template <typename F>
  void If(const YAML::Node& node, const char* key, const std::string& field, F apply) const {
    const YAML::Node child = node[key];
    if (child.IsDefined() && !child.IsNull()) apply(child, Join(field, key));
  }

  // If `key` is present: *out = its value, read as *out's type (errors name the field).
  void Set(const YAML::Node& node, const char* key, const std::string& field, double* out) const {
    If(node, key, field, [&](const YAML::Node& n, const std::string& f) { *out = Double(n, f); });
  }
  void Set(const YAML::Node& node, const char* key, const std::string& field, int* out) const {
    If(node, key, field, [&](const YAML::Node& n, const std::string& f) { *out = Int(n, f); });
  }
  void Set(const YAML::Node& node, const char* key, const std::string& field, bool* out) const {
    If(node, key, field, [&](const YAML::Node& n, const std::string& f) { *out = Bool(n, f); });
  }
  void Set(const YAML::Node& node, const char* key, const std::string& field,
           std::string* out) const {
    If(node, key, field, [&](const YAML::Node& n, const std::string& f) { *out = String(n, f); });
  }
  void Set(const YAML::Node& node, const char* key, const std::string& field,
           Eigen::Vector3d* out) const {
    If(node, key, field, [&](const YAML::Node& n, const std::string& f) { *out = Vector3(n, f); });
  }

 private:
  std::string file_;
};

}  // namespace config_internal
}  // namespace calibench
