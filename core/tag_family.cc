#include "core/tag_family.h"

#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagCircle21h7.h>
#include <apriltag/tagCircle49h12.h>
#include <apriltag/tagCustom48h12.h>
#include <apriltag/tagStandard41h12.h>
#include <apriltag/tagStandard52h13.h>

#include <map>

namespace calibench {
namespace {

const std::map<std::string, AprilTagFamilyFunctions>& Families() {
  static const std::map<std::string, AprilTagFamilyFunctions> families = {
      {"tag36h11", {tag36h11_create, tag36h11_destroy}},
      {"tag25h9", {tag25h9_create, tag25h9_destroy}},
      {"tag16h5", {tag16h5_create, tag16h5_destroy}},
      {"tagStandard41h12", {tagStandard41h12_create, tagStandard41h12_destroy}},
      {"tagStandard52h13", {tagStandard52h13_create, tagStandard52h13_destroy}},
      {"tagCircle21h7", {tagCircle21h7_create, tagCircle21h7_destroy}},
      {"tagCircle49h12", {tagCircle49h12_create, tagCircle49h12_destroy}},
      {"tagCustom48h12", {tagCustom48h12_create, tagCustom48h12_destroy}},
  };
  return families;
}

}  // namespace

bool FindAprilTagFamily(const std::string& name, AprilTagFamilyFunctions* functions) {
  const auto it = Families().find(name);
  if (it == Families().end()) return false;
  *functions = it->second;
  return true;
}

std::vector<std::string> TagFamily::Names() {
  std::vector<std::string> names;
  for (const auto& [name, f] : Families()) names.push_back(name);
  return names;
}

std::shared_ptr<const TagFamily> TagFamily::Create(const std::string& name, std::string* why) {
  const auto it = Families().find(name);
  if (it == Families().end()) {
    if (why) {
      *why = "unknown AprilTag family '" + name + "' (known:";
      for (const std::string& n : Names()) *why += " " + n;
      *why += ")";
    }
    return nullptr;
  }
  const std::unique_ptr<apriltag_family_t, void (*)(apriltag_family_t*)> fam(it->second.create(),
                                                                             it->second.destroy);
  auto family = std::make_shared<TagFamily>();
  family->name_ = name;
  family->num_codes_ = static_cast<int>(fam->ncodes);
  family->total_width_ = fam->total_width;
  family->width_at_border_ = fam->width_at_border;
  family->bitmaps_.resize(fam->ncodes);
  for (uint32_t id = 0; id < fam->ncodes; ++id) {
    const std::unique_ptr<image_u8_t, void (*)(image_u8_t*)> image(
        apriltag_to_image(fam.get(), static_cast<int>(id)), image_u8_destroy);
    std::vector<uint8_t>& cells = family->bitmaps_[id];
    cells.resize(static_cast<size_t>(fam->total_width) * fam->total_width);
    for (int row = 0; row < fam->total_width; ++row) {
      for (int col = 0; col < fam->total_width; ++col) {
        cells[static_cast<size_t>(row) * fam->total_width + col] =
            image->buf[row * image->stride + col] > 127 ? 1 : 0;
      }
    }
  }
  return family;
}

}  // namespace calibench
