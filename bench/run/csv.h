// CSV output (RFC 4180 quoting) written atomically: the file appears complete or not at all
// (write to PATH.tmp.<pid>, flush, rename over PATH).
#pragma once

#include <istream>
#include <string>
#include <vector>

#include "util/atomic_file.h"  // WriteFileAtomically: how a CSV file is written.
#include "util/format.h"       // FormatNumber: how a CSV file writes a number.

namespace calibench {

std::string CsvLine(const std::vector<std::string>& fields);

// Reads RFC 4180 records (quoted fields may hold commas, quotes and newlines) one at a time.
class CsvReader {
 public:
  explicit CsvReader(std::istream* in) : in_(in) {}
  // The next record into *fields; false at the end, or with *why on a malformed record (an
  // unterminated quote, or a last line without its newline: a file cut short).
  bool Next(std::vector<std::string>* fields, std::string* why);
  long record() const { return record_; }  // 1-based number of the record last read.

 private:
  std::istream* in_;
  long record_ = 0;
};

}  // namespace calibench
