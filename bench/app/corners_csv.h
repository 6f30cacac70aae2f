// `calibench detect --images ... --out corners.csv`: the corners calib/detect_images.h found, as
// the CSV text that header describes (RFC 4180, bench/run/csv.h).
#pragma once

#include <string>
#include <vector>

#include "calib/detect_images.h"

namespace calibench {

// The CSV text (header first): image,tag_id,corner,u_px,v_px,crlb_px, one row per corner.
std::string ImageCornersCsv(const std::vector<ImageCorners>& images);

}  // namespace calibench
