#include "bench/app/corners_csv.h"

#include "bench/run/csv.h"

namespace calibench {

std::string ImageCornersCsv(const std::vector<ImageCorners>& images) {
  std::string csv = CsvLine({"image", "tag_id", "corner", "u_px", "v_px", "crlb_px"});
  for (const ImageCorners& image : images) {
    for (const ImageCorners::Corner& c : image.corners) {
      csv += CsvLine({image.file, c.tag_id >= 0 ? std::to_string(c.tag_id) : "",
                      std::to_string(c.corner), FormatNumber(c.u_px), FormatNumber(c.v_px),
                      FormatNumber(c.crlb_px)});
    }
  }
  return csv;
}

}  // namespace calibench
