#pragma once
// Writes a whole text file for a command-line output flag (--json, --csv, ...):
// missing parent folders are created; a failure is a UserError naming the
// flag and the path.
#include <string>

namespace ml {

void writeTextFile(const std::string& path, const std::string& text, const std::string& flag);

}  // namespace ml
