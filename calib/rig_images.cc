#include "calib/rig_images.h"

#include <fnmatch.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "calib/image_points.h"

namespace calibench {
namespace {

namespace fs = std::filesystem;

bool IsDigit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

// The stems of one source with the common prefix and suffix removed (header comment, rule 1).
std::vector<std::string> StemMiddles(const std::vector<std::string>& stems) {
  if (stems.size() < 2) return stems;
  size_t prefix = stems[0].size(), suffix = stems[0].size();
  for (const std::string& s : stems) {
    size_t i = 0;
    while (i < prefix && i < s.size() && s[i] == stems[0][i]) ++i;
    prefix = i;
    size_t j = 0;
    while (j < suffix && j < s.size() && s[s.size() - 1 - j] == stems[0][stems[0].size() - 1 - j]) {
      ++j;
    }
    suffix = j;
  }
  // Never cut a run of digits: back off while the cut has a digit on both sides in any stem.
  const auto cuts_digits = [&](size_t at, const std::string& s) {
    return at > 0 && at < s.size() && IsDigit(s[at - 1]) && IsDigit(s[at]);
  };
  for (bool moved = true; moved;) {
    moved = false;
    for (const std::string& s : stems) {
      if (prefix > 0 && cuts_digits(prefix, s)) --prefix, moved = true;
      if (suffix > 0 && cuts_digits(s.size() - suffix, s)) --suffix, moved = true;
    }
  }
  std::vector<std::string> middles;
  for (const std::string& s : stems) {
    const size_t p = std::min(prefix, s.size());
    const size_t end = s.size() - std::min(suffix, s.size() - p);
    middles.push_back(s.substr(p, end - p));
  }
  return middles;
}

// The value of the last run of digits in `text` (leading zeros dropped: "07" -> "7"); empty when
// it has no digit.
std::string LastNumber(const std::string& text) {
  size_t end = text.size();
  while (end > 0 && !IsDigit(text[end - 1])) --end;
  if (end == 0) return "";
  size_t begin = end;
  while (begin > 0 && IsDigit(text[begin - 1])) --begin;
  while (begin + 1 < end && text[begin] == '0') ++begin;
  return text.substr(begin, end - begin);
}

// Keys in order: numbers by value (the same length first), text as text.
bool KeyLess(const std::string& a, const std::string& b, bool numbers) {
  if (numbers && a.size() != b.size()) return a.size() < b.size();
  return a < b;
}

}  // namespace

bool RigImageOptions::Check(std::string* why) const {
  if (min_cameras_per_frame < 2) {
    if (why) *why = "min_cameras_per_frame: at least 2 (a frame pairs cameras)";
    return false;
  }
  return true;
}

bool ListSourceImages(const std::string& source, std::vector<std::string>* files,
                      std::string* why) {
  files->clear();
  const fs::path path(source);
  const std::string pattern = path.filename().string();
  const bool glob = pattern.find_first_of("*?[") != std::string::npos;
  std::error_code ec;
  if (!glob) {
    if (fs::is_directory(path, ec)) return ListImageFiles(source, files, why);
    if (why) *why = source + ": neither a folder nor a glob of image files ('dir/left*.png')";
    return false;
  }
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  if (dir.string().find_first_of("*?[") != std::string::npos) {
    if (why) *why = source + ": a glob may have * ? [ ] in the file name only";
    return false;
  }
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (it->is_regular_file() && IsImageFile(it->path().string()) &&
        fnmatch(pattern.c_str(), name.c_str(), FNM_PERIOD) == 0) {
      files->push_back((dir / name).string());
    }
  }
  if (ec) {
    if (why) *why = source + ": cannot list " + dir.string() + ": " + ec.message();
    return false;
  }
  if (files->empty()) {
    if (why) *why = source + ": matches no image (png, jpg, jpeg, tif, tiff, bmp)";
    return false;
  }
  std::sort(files->begin(), files->end());
  return true;
}

RigImageSummary PairRigImages(const std::vector<std::string>& sources,
                              const RigImageOptions& options) {
  RigImageSummary summary;
  std::string why;
  if (!options.Check(&why)) {
    summary.error = "rig images: " + why;
    return summary;
  }
  const int n = static_cast<int>(sources.size());
  if (n < 2) {
    summary.error =
        "rig images: a rig needs at least 2 sources (one per camera), got " + std::to_string(n);
    return summary;
  }
  if (options.min_cameras_per_frame > n) {
    summary.error = "rig images: min_cameras_per_frame " +
                    std::to_string(options.min_cameras_per_frame) + " > " + std::to_string(n) +
                    " sources";
    return summary;
  }
  std::vector<std::vector<std::string>> files(n), middles(n);
  // Keyed by number when most of every source's names hold one (a stray unnumbered image, e.g.
  // left_test.png, is listed unpaired rather than switching every source to name keys).
  bool all_numbered = true;
  for (int s = 0; s < n; ++s) {
    if (!ListSourceImages(sources[s], &files[s], &why)) {
      summary.error = "camera " + std::to_string(s) + ": " + why;
      return summary;
    }
    summary.images_per_source.push_back(static_cast<int>(files[s].size()));
    std::vector<std::string> stems;
    for (const std::string& f : files[s]) stems.push_back(fs::path(f).stem().string());
    middles[s] = StemMiddles(stems);
    size_t numbered = 0;
    for (const std::string& m : middles[s]) numbered += LastNumber(m).empty() ? 0 : 1;
    all_numbered = all_numbered && 2 * numbered > middles[s].size();
  }
  summary.keyed_by_number = all_numbered;
  const auto less = [&](const std::string& a, const std::string& b) {
    return KeyLess(a, b, all_numbered);
  };
  // key -> per source the path.
  std::map<std::string, std::vector<std::string>, decltype(less)> by_key(less);
  for (int s = 0; s < n; ++s) {
    for (size_t i = 0; i < files[s].size(); ++i) {
      const std::string key = all_numbered ? LastNumber(middles[s][i]) : middles[s][i];
      if (key.empty()) {  // Keyed by number, this name has none.
        summary.unpaired.push_back({s, files[s][i]});
        continue;
      }
      std::vector<std::string>& paths = by_key[key];
      paths.resize(n);
      if (!paths[s].empty()) {
        summary.error =
            "camera " + std::to_string(s) + ": " + sources[s] + ": " + paths[s] + " and " +
            files[s][i] + " have the same key '" + key + "' (pairing is by the " +
            (all_numbered ? "number in the names" : "names less their common part") + ")";
        return summary;
      }
      paths[s] = files[s][i];
    }
  }
  for (const auto& [key, paths] : by_key) {
    int cameras = 0;
    for (const std::string& p : paths) cameras += p.empty() ? 0 : 1;
    if (cameras >= options.min_cameras_per_frame) {
      summary.frames.push_back({key, paths});
      continue;
    }
    for (int s = 0; s < n; ++s) {
      if (!paths[s].empty()) summary.unpaired.push_back({s, paths[s]});
    }
  }
  std::stable_sort(summary.unpaired.begin(), summary.unpaired.end(),
                   [](const UnpairedImage& a, const UnpairedImage& b) {
                     return a.source != b.source ? a.source < b.source : a.path < b.path;
                   });
  if (summary.frames.empty()) {
    std::ostringstream msg;
    msg << "rig images: no " << (all_numbered ? "number" : "name") << " is shared by "
        << options.min_cameras_per_frame << " sources (";
    for (int s = 0; s < n; ++s) {
      msg << (s ? "; " : "") << sources[s] << ": " << files[s].size() << " images, e.g. "
          << fs::path(files[s][0]).filename().string();
    }
    msg << ")";
    summary.error = msg.str();
    return summary;
  }
  summary.ok = true;
  return summary;
}

std::string RigImageSummary::Report(const std::vector<std::string>& sources) const {
  std::ostringstream out;
  for (size_t s = 0; s < images_per_source.size(); ++s) {
    out << "camera " << s << ": " << (s < sources.size() ? sources[s] : "") << ": "
        << images_per_source[s] << " images\n";
  }
  out << frames.size() << " frames paired by "
      << (keyed_by_number ? "the number in the names" : "the names") << ", " << unpaired.size()
      << " images unpaired\n";
  for (const UnpairedImage& u : unpaired) {
    out << "  unpaired (camera " << u.source << "): " << u.path << "\n";
  }
  if (!error.empty()) out << "error: " << error << "\n";
  return out.str();
}

}  // namespace calibench
