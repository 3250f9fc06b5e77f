#include "host/util/TextFile.hpp"

#include <filesystem>
#include <fstream>

#include "host/util/Error.hpp"

namespace ml {

void writeTextFile(const std::string& path, const std::string& text, const std::string& flag) {
  namespace fs = std::filesystem;
  const fs::path parent = fs::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) fs::create_directories(parent, ec);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw UserError(flag + ": cannot write '" + path + "'");
  out << text;
  out.close();
  if (!out) throw UserError(flag + ": writing '" + path + "' failed");
}

}  // namespace ml
