// AprilTag families as the apriltag library defines them: the code bitmaps the renderer paints and
// the detector decodes, never hand-typed.
//
// Bitmap layout (apriltag_to_image): total_width x total_width cells, row 0 at the top; the tag's
// reference square — whose corners the detector reports — is the width_at_border x width_at_border
// block starting at cell (border_start, border_start), border_start = (total - width_at_border)/2.
//
// Black border width. The library's families have a black border 1 cell wide (AprilTag 3's
// layout); Kalibr's AprilGrids print tag36h11 with a border `border_bits` = 2 cells wide (Kalibr's
// blackTagBorder). A family with b border bits is the library's family grown by b - 1 rings of
// black cells: width_at_border and total_width are 2 (b - 1) larger and every data bit moves by
// b - 1 cells along x and y (bit_x, bit_y are counted from the reference square's top-left cell),
// with the same codes. This is exactly what quad_decode samples (apriltag.c): the border model is
// read half a cell inside and outside the reference square's edges, data bit i at
// ((bit_x + 0.5) / width_at_border, (bit_y + 0.5) / width_at_border) of it. Only families whose
// border is black (reversed_border = false: tag36h11, tag25h9, tag16h5) can be grown so; the
// others (tagStandard*, tagCircle*, tagCustom*) take border_bits = 1 only.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

struct apriltag_family;

namespace calibench {

// The apriltag library's constructor / destructor pair of a family, by name (see Names()).
struct AprilTagFamilyFunctions {
  apriltag_family* (*create)() = nullptr;
  void (*destroy)(apriltag_family*) = nullptr;
};
bool FindAprilTagFamily(const std::string& name, AprilTagFamilyFunctions* functions);

// Border widths a family may have: 1 (AprilTag 3) or 2 (Kalibr). Kalibr's detector and its
// kalibr_create_target_pdf are used with 1 and 2 only; wider borders waste the tag's area.
constexpr int kMinBorderBits = 1, kMaxBorderBits = 2;
// False with *why when `name` is unknown, border_bits is outside [kMinBorderBits, kMaxBorderBits]
// or the family's border is white (reversed) and border_bits != 1.
bool CheckBorderBits(const std::string& name, int border_bits, std::string* why);
// The number of codes (tag ids 0 .. n - 1) of family `name`; 0 for an unknown name. Each family is
// read once (thread-safe).
int NumAprilTagCodes(const std::string& name);

// An apriltag_family for the detector with `border_bits` black border cells (see above), owning
// what it allocates: the library's family, and for border_bits > 1 a derived copy whose bit
// tables are ours (its codes are the library family's, which stays alive beside it). The
// detector's decoding table (family->impl) is freed by apriltag_detector_destroy: destroy the
// detector before this handle.
class AprilTagFamilyHandle {
 public:
  // nullptr (and *why) when CheckBorderBits refuses, or the library cannot allocate.
  static std::unique_ptr<AprilTagFamilyHandle> Create(const std::string& name, int border_bits,
                                                      std::string* why);
  ~AprilTagFamilyHandle();
  AprilTagFamilyHandle(const AprilTagFamilyHandle&) = delete;
  AprilTagFamilyHandle& operator=(const AprilTagFamilyHandle&) = delete;
  apriltag_family* get() const { return derived_ ? derived_.get() : base_; }

 private:
  AprilTagFamilyHandle() = default;
  apriltag_family* base_ = nullptr;
  void (*destroy_)(apriltag_family*) = nullptr;
  std::unique_ptr<apriltag_family> derived_;  // Only for border_bits > 1.
  std::vector<uint32_t> bit_x_, bit_y_;
  std::string name_;
};

class TagFamily {
 public:
  // "tag36h11", "tag25h9", "tag16h5", "tagStandard41h12", "tagStandard52h13", "tagCircle21h7",
  // "tagCircle49h12", "tagCustom48h12". nullptr (and *why) for another name.
  static std::shared_ptr<const TagFamily> Create(const std::string& name, std::string* why);
  // With `border_bits` black border cells (CheckBorderBits): the bitmaps of Kalibr's AprilGrid tags
  // for border_bits = 2.
  static std::shared_ptr<const TagFamily> Create(const std::string& name, int border_bits,
                                                 std::string* why);
  static std::vector<std::string> Names();

  const std::string& name() const { return name_; }
  int border_bits() const { return border_bits_; }
  int num_codes() const { return num_codes_; }
  int total_width() const { return total_width_; }
  int width_at_border() const { return width_at_border_; }
  int border_start() const { return (total_width_ - width_at_border_) / 2; }
  // Cell (col, row) of tag `id`: true = white. id must be in [0, num_codes).
  bool IsWhite(int id, int col, int row) const {
    return bitmaps_[id][static_cast<size_t>(row) * total_width_ + col] != 0;
  }

 private:
  std::string name_;
  int num_codes_ = 0, total_width_ = 0, width_at_border_ = 0, border_bits_ = 1;
  std::vector<std::vector<uint8_t>> bitmaps_;  // Per id, total_width^2 cells, row-major.
};

}  // namespace calibench
