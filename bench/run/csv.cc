#include "bench/run/csv.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

namespace calibench {

std::string CsvLine(const std::vector<std::string>& fields) {
  std::string line;
  for (size_t i = 0; i < fields.size(); ++i) {
    if (i) line += ',';
    const std::string& f = fields[i];
    if (f.find_first_of(",\"\n\r") == std::string::npos) {
      line += f;
      continue;
    }
    line += '"';
    for (char c : f) line += c == '"' ? std::string("\"\"") : std::string(1, c);
    line += '"';
  }
  return line + "\n";
}

bool CsvReader::Next(std::vector<std::string>* fields, std::string* why) {
  fields->clear();
  if (why) why->clear();
  if (in_->peek() == std::char_traits<char>::eof()) return false;
  ++record_;
  std::string field;
  bool quoted = false;
  bool was_quoted = false;
  char c;
  while (in_->get(c)) {
    if (quoted) {
      if (c != '"') {
        field += c;
      } else if (in_->peek() == '"') {
        in_->get(c);
        field += '"';
      } else {
        quoted = false;
      }
      continue;
    }
    if (c == '"' && field.empty() && !was_quoted) {
      quoted = was_quoted = true;
    } else if (c == ',') {
      fields->push_back(field);
      field.clear();
      was_quoted = false;
    } else if (c == '\n') {
      fields->push_back(field);
      return true;
    } else if (c != '\r') {
      field += c;
    }
  }
  if (why) {
    *why = "record " + std::to_string(record_) +
           (quoted ? ": unterminated quoted field" : ": the last line has no newline (cut short?)");
  }
  return false;
}

}  // namespace calibench
