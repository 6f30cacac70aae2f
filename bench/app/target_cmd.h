// `calibench target`: a printable calibration target at exact physical size, with the Kalibr
// target YAML that describes it.
//
//   calibench target --type aprilgrid --rows 6 --cols 6 --size 0.088 --spacing 0.3 --border 2
//       --first-id 0 --margin 0.02 --dpi 300 --out board.pdf
// writes board.pdf (vector), board.png (raster at --dpi) and board.yaml beside it.
//
// Layout, in metres on the board (x right, y up; the origin is the bottom-left corner of the first
// tag's black square, or of the checkerboard's first inner corner):
//   aprilgrid: Kalibr's (sim/target.h, kalibr_create_target_pdf): tag (r, c) with id
//     first_id + r cols + c has its black square at (c p, r p), p = size (1 + spacing); the cells
//     of the family's bitmap with `border` black border bits (sim/tag_family.h), bitmap row 0 at
//     the square's top; black squares of edge spacing * size at the four corners of every tag.
//   checkerboard: rows x cols inner corners (Kalibr's targetRows / targetCols), squares of edge
//     size; the square with its lower-left corner at ((i - 1) size, (j - 1) size) is black when
//     i + j is even (i, j >= 0), so the bottom-left square is black.
//   the page: the pattern's bounding box plus `margin` on each side.
// PDF: one page, MediaBox = the page in points (1 m = 72 / 0.0254 pt), the black rectangles as
// filled paths ("x y w h re f") in one uncompressed content stream; print at 100% ("actual size").
// PNG: 8-bit gray at `dpi`; a pixel's gray is 255 (1 - the black area it covers), exact for
// axis-aligned rectangles; pixel (i, j) covers [i - 0.5, i + 0.5] x [j - 0.5, j + 0.5] page pixels
// from the page's top-left corner (calibench's convention). All three files are written
// atomically.
#pragma once

#include <string>
#include <vector>

#include "io/target_io.h"

namespace calibench {

struct TargetArgs {
  std::string type = "aprilgrid";  // aprilgrid | checkerboard.
  int rows = 6, cols = 6;          // Tags (aprilgrid) or inner corners (checkerboard).
  double size_m = 0.088;           // Tag edge (border included) or square edge.
  double spacing = 0.3;            // aprilgrid: gap / tag edge.
  int border_bits = 2;             // aprilgrid: 1 or 2.
  std::string family = "tag36h11";
  int first_id = 0;
  double margin_m = 0.02;  // White margin around the pattern.
  double dpi = 300;        // The PNG's resolution.
  std::string out_path = "board.pdf";
  bool Check(std::string* why) const;
};

struct BlackRect {
  double x, y, w, h;  // Metres on the page, from its bottom-left corner.
};

struct TargetLayout {
  double page_w_m = 0, page_h_m = 0;
  std::vector<BlackRect> rects;
  CalibrationTarget target;  // What board.yaml says.
  // The page point (m, from the page's bottom-left) of the board frame's origin.
  double origin_x_m = 0, origin_y_m = 0;
};

// False with *why for invalid arguments (or a family without enough codes).
bool MakeTargetLayout(const TargetArgs& args, TargetLayout* layout, std::string* why);
std::string TargetPdf(const TargetLayout& layout);
// Gray pixels, row-major, row 0 at the page's top; *width x *height.
std::vector<uint8_t> RasterizeTarget(const TargetLayout& layout, double dpi, int* width,
                                     int* height);

// 0 on success; 2 for bad arguments; 3 when a file cannot be written. Says what it wrote.
int WriteTarget(const TargetArgs& args);

}  // namespace calibench
