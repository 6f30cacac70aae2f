// Writing a file so that it appears complete or not at all: the contents go to PATH.tmp.<pid>,
// are flushed to disk (fsync), then renamed over PATH. A reader never sees half a file; a crash
// leaves PATH as it was.
#pragma once

#include <string>

namespace calibench {

// False with *why naming the path and the reason (cannot create, write failed, rename failed).
bool WriteFileAtomically(const std::string& path, const std::string& contents, std::string* why);

}  // namespace calibench
