// AprilTag families as the apriltag library defines them: the code bitmaps the renderer paints and
// the detector decodes, never hand-typed.
//
// Bitmap layout (apriltag_to_image): total_width x total_width cells, row 0 at the top; the tag's
// reference square — whose corners the detector reports — is the width_at_border x width_at_border
// block starting at cell (border_start, border_start), border_start = (total - width_at_border)/2.
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

class TagFamily {
 public:
  // "tag36h11", "tag25h9", "tag16h5", "tagStandard41h12", "tagStandard52h13", "tagCircle21h7",
  // "tagCircle49h12", "tagCustom48h12". nullptr (and *why) for another name.
  static std::shared_ptr<const TagFamily> Create(const std::string& name, std::string* why);
  static std::vector<std::string> Names();

  const std::string& name() const { return name_; }
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
  int num_codes_ = 0, total_width_ = 0, width_at_border_ = 0;
  std::vector<std::vector<uint8_t>> bitmaps_;  // Per id, total_width^2 cells, row-major.
};

}  // namespace calibench
