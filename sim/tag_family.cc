#include "sim/tag_family.h"

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

bool CheckBorderBits(const std::string& name, int border_bits, std::string* why) {
  std::string msg;
  AprilTagFamilyFunctions f;
  if (!FindAprilTagFamily(name, &f)) {
    msg = "unknown AprilTag family '" + name + "'";
  } else if (border_bits < kMinBorderBits || border_bits > kMaxBorderBits) {
    msg = "black border of " + std::to_string(border_bits) + " bits: must be 1 (AprilTag 3) or " +
          "2 (Kalibr's AprilGrid)";
  } else if (border_bits != 1) {
    const std::unique_ptr<apriltag_family_t, void (*)(apriltag_family_t*)> fam(f.create(),
                                                                               f.destroy);
    if (fam && fam->reversed_border) {
      msg = name + " has a white (reversed) border: only a 1-bit border is defined for it";
    }
  }
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

std::unique_ptr<AprilTagFamilyHandle> AprilTagFamilyHandle::Create(const std::string& name,
                                                                   int border_bits,
                                                                   std::string* why) {
  if (!CheckBorderBits(name, border_bits, why)) return nullptr;
  AprilTagFamilyFunctions f;
  if (!FindAprilTagFamily(name, &f) || f.create == nullptr) {
    if (why) *why = "unknown AprilTag family '" + name + "'";
    return nullptr;
  }
  std::unique_ptr<AprilTagFamilyHandle> h(new AprilTagFamilyHandle());
  h->base_ = f.create();
  h->destroy_ = f.destroy;
  if (h->base_ == nullptr) {
    if (why) *why = "apriltag: cannot create family " + name;
    return nullptr;
  }
  if (border_bits == 1) return h;
  const apriltag_family_t& base = *h->base_;
  const int grow = border_bits - 1;  // Extra black rings.
  h->bit_x_.assign(base.bit_x, base.bit_x + base.nbits);
  h->bit_y_.assign(base.bit_y, base.bit_y + base.nbits);
  for (uint32_t& x : h->bit_x_) x += grow;
  for (uint32_t& y : h->bit_y_) y += grow;
  h->name_ = name + "_border" + std::to_string(border_bits);
  h->derived_ = std::make_unique<apriltag_family_t>(base);  // Codes shared with base.
  apriltag_family_t& d = *h->derived_;
  d.width_at_border = base.width_at_border + 2 * grow;
  d.total_width = base.total_width + 2 * grow;
  d.bit_x = h->bit_x_.data();
  d.bit_y = h->bit_y_.data();
  d.name = h->name_.data();
  d.impl = nullptr;  // The detector's own decoding table, built when the family is added.
  return h;
}

int NumAprilTagCodes(const std::string& name) {
  static const std::map<std::string, int> counts = [] {
    std::map<std::string, int> c;
    for (const auto& [n, f] : Families()) {
      apriltag_family* family = f.create();
      c[n] = family != nullptr ? static_cast<int>(family->ncodes) : 0;
      if (family != nullptr) f.destroy(family);
    }
    return c;
  }();
  const auto it = counts.find(name);
  return it == counts.end() ? 0 : it->second;
}

AprilTagFamilyHandle::~AprilTagFamilyHandle() {
  derived_.reset();
  if (base_ != nullptr) destroy_(base_);
}

std::vector<std::string> TagFamily::Names() {
  std::vector<std::string> names;
  for (const auto& [name, f] : Families()) names.push_back(name);
  return names;
}

std::shared_ptr<const TagFamily> TagFamily::Create(const std::string& name, std::string* why) {
  return Create(name, 1, why);
}

std::shared_ptr<const TagFamily> TagFamily::Create(const std::string& name, int border_bits,
                                                   std::string* why) {
  const auto it = Families().find(name);
  if (it == Families().end()) {
    if (why) {
      *why = "unknown AprilTag family '" + name + "' (known:";
      for (const std::string& n : Names()) *why += " " + n;
      *why += ")";
    }
    return nullptr;
  }
  const std::unique_ptr<AprilTagFamilyHandle> handle =
      AprilTagFamilyHandle::Create(name, border_bits, why);
  if (!handle) return nullptr;
  const apriltag_family_t* fam = handle->get();
  auto family = std::make_shared<TagFamily>();
  family->name_ = name;
  family->border_bits_ = border_bits;
  family->num_codes_ = static_cast<int>(fam->ncodes);
  family->total_width_ = fam->total_width;
  family->width_at_border_ = fam->width_at_border;
  family->bitmaps_.resize(fam->ncodes);
  for (uint32_t id = 0; id < fam->ncodes; ++id) {
    const std::unique_ptr<image_u8_t, void (*)(image_u8_t*)> image(
        apriltag_to_image(const_cast<apriltag_family_t*>(fam), static_cast<int>(id)),
        image_u8_destroy);
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
