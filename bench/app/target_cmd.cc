#include "bench/app/target_cmd.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <tuple>

#include "bench/run/csv.h"
#include "sim/tag_family.h"

namespace calibench {
namespace {

constexpr double kPointsPerMetre = 72.0 / 0.0254;
constexpr double kMaxPagePixels = 400e6;    // The PNG: 20000 x 20000 px at most.
constexpr int64_t kMaxSquares = 1'000'000;  // A PDF of ~40 MB.

// "x y w h re f" numbers: 1e-4 pt (35 nm) resolution.
std::string Pt(double metres) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.4f", metres * kPointsPerMetre);
  return text;
}

}  // namespace

bool TargetArgs::Check(std::string* why) const {
  std::string msg;
  const bool grid = type == "aprilgrid";
  if (!grid && type != "checkerboard") msg = "--type must be aprilgrid or checkerboard";
  if (rows < (grid ? 1 : 2) || cols < (grid ? 1 : 2)) {
    msg = grid ? "--rows and --cols (tags) must be >= 1"
               : "--rows and --cols (inner corners) must be >= 2";
  }
  // (rows + 1) x (cols + 1) squares (a checkerboard's; an AprilGrid's corner squares), each a
  // rectangle of the PDF and of the layout, counted before any is built.
  if ((static_cast<int64_t>(rows) + 1) * (static_cast<int64_t>(cols) + 1) > kMaxSquares) {
    msg = "--rows x --cols: at most " + std::to_string(kMaxSquares) + " squares on a page";
  }
  if (!(size_m > 0 && size_m < 10)) msg = "--size must lie in (0, 10) m";
  if (grid && !(spacing > 0 && spacing <= 1)) {
    msg = "--spacing must lie in (0, 1] (Kalibr's range; a fraction of the tag size)";
  }
  std::string border_why;
  if (grid && !CheckBorderBits(family, border_bits, &border_why)) msg = "--border: " + border_why;
  if (first_id < 0) msg = "--first-id must be >= 0";
  if (!(margin_m >= 0 && margin_m < 10)) msg = "--margin must lie in [0, 10) m";
  if (!(dpi >= 10 && dpi <= 2400)) msg = "--dpi must lie in [10, 2400]";
  if (std::filesystem::path(out_path).extension() != ".pdf") {
    msg = "--out must name a .pdf file (the .png and .yaml are written beside it)";
  }
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

namespace {

// The pattern's black rectangles in the board frame (metres) and their bounding box.
struct BoardPattern {
  std::vector<BlackRect> rects;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// An AprilGrid (Kalibr's: corner squares included, each once): every tag's black cells, merged
// into runs along each bitmap row. False (and *why) for a family without enough codes.
bool AprilGridPattern(const TargetArgs& a, AprilGrid* g, BoardPattern* out, std::string* why) {
  g->family = a.family;
  g->tag_rows = a.rows;
  g->tag_cols = a.cols;
  g->tag_size_m = a.size_m;
  g->tag_spacing = a.spacing;
  g->first_id = a.first_id;
  g->black_tag_border = a.border_bits;
  g->corner_squares = true;
  if (!g->Check(why)) return false;  // Ids past the family's codes, among others.
  const auto family = TagFamily::Create(g->family, g->black_tag_border, why);
  if (!family) return false;
  const double s = g->tag_size_m, p = g->Pitch(), gap = g->tag_spacing * s;
  const int wab = family->width_at_border(), start = family->border_start();
  const double cell = s / wab;
  std::set<std::tuple<long, long>> squares;  // Corner squares shared by neighbours: once.
  for (int r = 0; r < g->tag_rows; ++r) {
    for (int c = 0; c < g->tag_cols; ++c) {
      const int id = g->first_id + r * g->tag_cols + c;
      const double tx = c * p, ty = r * p;
      for (int row = 0; row < wab; ++row) {  // Runs of black cells along each row.
        for (int col = 0; col < wab;) {
          if (family->IsWhite(id, col + start, row + start)) {
            ++col;
            continue;
          }
          int end = col;
          while (end < wab && !family->IsWhite(id, end + start, row + start)) ++end;
          out->rects.push_back(
              {tx + col * cell, ty + s - (row + 1) * cell, (end - col) * cell, cell});
          col = end;
        }
      }
      for (int corner = 0; corner < 4; ++corner) {
        const double cx = corner == 1 || corner == 2 ? tx + s : tx - gap;
        const double cy = corner >= 2 ? ty + s : ty - gap;
        // Squares sit at (k p - gap, l p - gap), k, l integers: keyed on (k, l).
        if (squares.insert({std::lround((cx + gap) / p), std::lround((cy + gap) / p)}).second) {
          out->rects.push_back({cx, cy, gap, gap});
        }
      }
    }
  }
  out->x0 = out->y0 = -gap;
  out->x1 = (g->tag_cols - 1) * p + s + gap;
  out->y1 = (g->tag_rows - 1) * p + s + gap;
  return true;
}

// A checkerboard of rows x cols inner corners: (rows + 1) x (cols + 1) squares, the black ones.
BoardPattern CheckerboardPattern(const TargetArgs& a) {
  BoardPattern out;
  const double s = a.size_m;
  for (int j = 0; j <= a.rows; ++j) {
    for (int i = 0; i <= a.cols; ++i) {
      if ((i + j) % 2 == 0) out.rects.push_back({(i - 1) * s, (j - 1) * s, s, s});
    }
  }
  out.x0 = out.y0 = -s;
  out.x1 = a.cols * s;
  out.y1 = a.rows * s;
  return out;
}

}  // namespace

bool MakeTargetLayout(const TargetArgs& a, TargetLayout* layout, std::string* why) {
  if (!a.Check(why)) return false;
  *layout = TargetLayout();
  BoardPattern board;
  CalibrationTarget& t = layout->target;
  if (a.type == "aprilgrid") {
    t.type = CalibrationTarget::Type::kAprilGrid;
    if (!AprilGridPattern(a, &t.grid, &board, why)) return false;
  } else {
    t.type = CalibrationTarget::Type::kCheckerboard;
    t.rows = a.rows;
    t.cols = a.cols;
    t.row_spacing_m = t.col_spacing_m = a.size_m;
    board = CheckerboardPattern(a);
  }
  layout->page_w_m = board.x1 - board.x0 + 2 * a.margin_m;
  layout->page_h_m = board.y1 - board.y0 + 2 * a.margin_m;
  layout->origin_x_m = a.margin_m - board.x0;
  layout->origin_y_m = a.margin_m - board.y0;
  for (BlackRect r : board.rects) {
    r.x += layout->origin_x_m;
    r.y += layout->origin_y_m;
    layout->rects.push_back(r);
  }
  const double pixels = layout->page_w_m * layout->page_h_m * std::pow(a.dpi / 0.0254, 2);
  if (pixels > kMaxPagePixels) {
    if (why) *why = "the PNG would have more than 400 Mpx: lower --dpi";
    return false;
  }
  return true;
}

std::string TargetPdf(const TargetLayout& layout) {
  std::string content = "0 g\n";  // Black fill.
  for (const BlackRect& r : layout.rects) {
    content += Pt(r.x) + " " + Pt(r.y) + " " + Pt(r.w) + " " + Pt(r.h) + " re f\n";
  }
  const std::string objects[] = {
      "<< /Type /Catalog /Pages 2 0 R >>",
      "<< /Type /Pages /Kids [3 0 R] /Count 1 >>",
      "<< /Type /Page /Parent 2 0 R /MediaBox [0 0 " + Pt(layout.page_w_m) + " " +
          Pt(layout.page_h_m) + "] /Contents 4 0 R /Resources << >> >>",
      "<< /Length " + std::to_string(content.size()) + " >>\nstream\n" + content + "endstream",
  };
  std::string pdf = "%PDF-1.4\n";
  std::vector<size_t> offsets;
  for (size_t i = 0; i < 4; ++i) {
    offsets.push_back(pdf.size());
    pdf += std::to_string(i + 1) + " 0 obj\n" + objects[i] + "\nendobj\n";
  }
  const size_t xref = pdf.size();
  pdf += "xref\n0 5\n0000000000 65535 f \n";
  for (size_t offset : offsets) {
    char line[32];
    std::snprintf(line, sizeof(line), "%010zu 00000 n \n", offset);
    pdf += line;
  }
  pdf += "trailer\n<< /Size 5 /Root 1 0 R >>\nstartxref\n" + std::to_string(xref) + "\n%%EOF\n";
  return pdf;
}

std::vector<uint8_t> RasterizeTarget(const TargetLayout& layout, double dpi, int* width,
                                     int* height) {
  const double px_per_m = dpi / 0.0254;
  *width = std::max(1, static_cast<int>(std::lround(layout.page_w_m * px_per_m)));
  *height = std::max(1, static_cast<int>(std::lround(layout.page_h_m * px_per_m)));
  const int w = *width, h = *height;
  std::vector<float> black(static_cast<size_t>(w) * h, 0.0f);
  for (const BlackRect& r : layout.rects) {
    // Page pixel edges: u from the left, v from the top; pixel i spans [i, i + 1] in them.
    const double u0 = r.x * px_per_m, u1 = (r.x + r.w) * px_per_m;
    const double v0 = (layout.page_h_m - r.y - r.h) * px_per_m;
    const double v1 = (layout.page_h_m - r.y) * px_per_m;
    const int i0 = std::max(0, static_cast<int>(std::floor(u0)));
    const int i1 = std::min(w - 1, static_cast<int>(std::ceil(u1)) - 1);
    const int j0 = std::max(0, static_cast<int>(std::floor(v0)));
    const int j1 = std::min(h - 1, static_cast<int>(std::ceil(v1)) - 1);
    for (int j = j0; j <= j1; ++j) {
      const double fy = std::min<double>(j + 1, v1) - std::max<double>(j, v0);
      for (int i = i0; i <= i1; ++i) {
        const double fx = std::min<double>(i + 1, u1) - std::max<double>(i, u0);
        black[static_cast<size_t>(j) * w + i] += static_cast<float>(fx * fy);
      }
    }
  }
  std::vector<uint8_t> gray(black.size());
  for (size_t k = 0; k < black.size(); ++k) {
    gray[k] = static_cast<uint8_t>(std::lround(255.0 * (1.0 - std::min(1.0f, black[k]))));
  }
  return gray;
}

int WriteTarget(const TargetArgs& args) {
  TargetLayout layout;
  std::string why;
  if (!MakeTargetLayout(args, &layout, &why)) {
    std::cerr << "calibench: target: " << why << "\n";
    return 2;
  }
  std::filesystem::path stem(args.out_path);
  stem.replace_extension();
  const std::string png_path = stem.string() + ".png", yaml_path = stem.string() + ".yaml";
  int w = 0, h = 0;
  std::vector<uint8_t> gray = RasterizeTarget(layout, args.dpi, &w, &h);
  std::vector<uint8_t> png;
  const cv::Mat mat(h, w, CV_8UC1, gray.data());
  bool encoded = false;
  try {
    encoded = cv::imencode(".png", mat, png);
  } catch (const cv::Exception& e) {
    encoded = false;
  }
  if (!encoded) {
    std::cerr << "calibench: target: " << png_path << ": cannot encode the PNG\n";
    return 3;
  }
  if (!WriteFileAtomically(args.out_path, TargetPdf(layout), &why) ||
      !WriteFileAtomically(png_path, std::string(png.begin(), png.end()), &why) ||
      !WriteFileAtomically(yaml_path, TargetYamlText(layout.target), &why)) {
    std::cerr << "calibench: target: " << why << "\n";
    return 3;
  }
  std::printf(
      "page %.1f x %.1f mm; wrote %s (vector, print at 100%%), %s (%d x %d px at %g dpi), %s\n",
      layout.page_w_m * 1e3, layout.page_h_m * 1e3, args.out_path.c_str(), png_path.c_str(), w, h,
      args.dpi, yaml_path.c_str());
  return 0;
}

}  // namespace calibench
