#include "ml_build_paths.h"  // MANYLIGHTS_SOURCE_DIR (generated)
#include "host/util/DataPaths.hpp"

#include <cstdlib>
#include <filesystem>

namespace ml {
namespace fs = std::filesystem;

std::string dataDir() {
  if (const char* env = std::getenv("MANYLIGHTS_DATA_DIR"); env && *env) return env;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    for (const fs::path& cand : {exe.parent_path() / ".." / "data", exe.parent_path() / ".." / ".." / "data"})
      if (fs::exists(cand / "default", ec)) return fs::weakly_canonical(cand, ec).string();
  }
  return std::string(MANYLIGHTS_SOURCE_DIR) + "/data";
}

std::string dataPath(const std::string& relative) { return dataDir() + "/" + relative; }

}  // namespace ml
