#include "io/points_io.h"

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <sstream>

namespace calibench {
namespace {

namespace fs = std::filesystem;

// Reads all whitespace-separated numbers of a text file.
bool ReadNumbers(const std::string& path, std::vector<double>* numbers, std::string* why) {
  std::ifstream in(path);
  if (!in) {
    if (why) *why = path + ": cannot open for reading";
    return false;
  }
  numbers->clear();
  std::string token;
  while (in >> token) {
    try {
      size_t used = 0;
      numbers->push_back(std::stod(token, &used));
      if (used != token.size()) throw std::invalid_argument(token);
    } catch (const std::exception&) {
      if (numbers->empty() || path.size() < 4 || path.substr(path.size() - 4) != ".dat") {
        if (why) *why = path + ": '" + token + "' is not a number";
        return false;
      }
      break;  // calib1.dat ends with free text after its numbers.
    }
  }
  return true;
}

bool LoadZhang(const std::string& dir, PointData* data, std::string* why) {
  std::vector<double> model;
  if (!ReadNumbers((fs::path(dir) / "Model.txt").string(), &model, why)) return false;
  if (model.empty() || model.size() % 2 != 0) {
    if (why) *why = dir + "/Model.txt: expected x y pairs";
    return false;
  }
  data->format = "zhang";
  for (int k = 1;; ++k) {
    const fs::path file = fs::path(dir) / ("data" + std::to_string(k) + ".txt");
    if (!fs::exists(file)) break;
    std::vector<double> pixels;
    if (!ReadNumbers(file.string(), &pixels, why)) return false;
    if (pixels.size() != model.size()) {
      if (why) {
        *why = file.string() + ": " + std::to_string(pixels.size() / 2) +
               " corners, Model.txt has " + std::to_string(model.size() / 2);
      }
      return false;
    }
    View view;
    for (size_t i = 0; i < model.size(); i += 2) {
      view.points.emplace_back(model[i], model[i + 1], 0.0);
      view.pixels.emplace_back(pixels[i], pixels[i + 1]);
    }
    data->views.push_back(std::move(view));
    data->view_names.push_back(file.filename().string());
  }
  if (data->views.empty()) {
    if (why) *why = dir + ": no data1.txt (Zhang's format needs Model.txt and data1.txt, ...)";
    return false;
  }
  return true;
}

bool LoadOpenCvCalib(const std::string& path, PointData* data, std::string* why) {
  std::vector<double> v;
  if (!ReadNumbers(path, &v, why)) return false;
  auto fail = [&](const std::string& reason) {
    if (why) *why = path + ": " + reason;
    return false;
  };
  if (v.size() < 6) return fail("truncated header");
  data->format = "opencv-calib";
  data->image_width = static_cast<int>(v[0]);
  data->image_height = static_cast<int>(v[1]);
  const int per_view = static_cast<int>(v[2] * v[3]);
  const int views = static_cast<int>(v[4]);
  if (per_view <= 0 || views <= 0) return fail("invalid pattern size or view count");
  size_t at = 6;
  const size_t needed = at + static_cast<size_t>(views) * per_view * 5;
  if (v.size() < needed) return fail("truncated point blocks");
  data->views.assign(views, View());
  for (View& view : data->views) {
    for (int i = 0; i < per_view; ++i, at += 3)
      view.points.emplace_back(v[at], v[at + 1], v[at + 2]);
  }
  for (View& view : data->views) {
    for (int i = 0; i < per_view; ++i, at += 2) view.pixels.emplace_back(v[at], v[at + 1]);
  }
  if (v.size() >= at + 8) {
    CameraIntrinsics ref;
    ref.fku_px = v[at];
    ref.fkv_px = v[at + 1];
    ref.u0_px = v[at + 2];
    ref.v0_px = v[at + 3];
    ref.k1 = v[at + 4];
    ref.k2 = v[at + 5];
    ref.p1 = v[at + 6];
    ref.p2 = v[at + 7];
    data->reference = ref;
  }
  return true;
}

}  // namespace

bool LoadPointData(const std::string& path, PointData* data, std::string* why) {
  *data = PointData();
  std::error_code ec;
  if (fs::is_directory(path, ec)) return LoadZhang(path, data, why);
  if (fs::is_regular_file(path, ec)) return LoadOpenCvCalib(path, data, why);
  if (why) *why = path + ": no such file or folder";
  return false;
}
}  // namespace calibench
