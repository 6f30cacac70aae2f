#include "util/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace calibench {

bool WriteFileAtomically(const std::string& path, const std::string& contents, std::string* why) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  auto fail = [&](const std::string& what) {
    if (why) *why = path + ": " + what + ": " + std::strerror(errno);
    std::remove(tmp.c_str());
    return false;
  };
  FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) return fail("cannot create the file");
  const bool wrote = std::fwrite(contents.data(), 1, contents.size(), f) == contents.size();
  const bool flushed = std::fflush(f) == 0 && ::fsync(fileno(f)) == 0;
  if (std::fclose(f) != 0 || !wrote || !flushed) return fail("write failed");
  if (std::rename(tmp.c_str(), path.c_str()) != 0) return fail("rename failed");
  return true;
}

}  // namespace calibench
