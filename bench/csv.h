// CSV output (RFC 4180 quoting) written atomically: the file appears complete or not at all
// (write to PATH.tmp.<pid>, flush, rename over PATH).
#pragma once

#include <string>
#include <vector>

namespace calibench {

std::string CsvLine(const std::vector<std::string>& fields);
// Writes `contents` to `path` atomically. Returns false with a reason naming the path.
bool WriteFileAtomically(const std::string& path, const std::string& contents, std::string* why);

}  // namespace calibench
