#include "host/util/EmbeddedFiles.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/util/Error.hpp"

namespace ml {
namespace {

// "kernels/f/x.cl" -> "<src>/kernels/f/x.cl", "shared/x.h" -> "<src>/host/shared/x.h",
// "shaders/f/x" -> "<src>/gl/shaders/f/x".
std::string diskPath(const std::string& root, std::string_view name) {
  std::string n(name);
  if (n.rfind("shared/", 0) == 0) return root + "/host/" + n;
  if (n.rfind("shaders/", 0) == 0) return root + "/gl/" + n;
  return root + "/" + n;
}

}  // namespace

std::string sourceDirFromEnv() {
  const char* root = std::getenv("MANYLIGHTS_SOURCE_DIR");
  if (!root || !*root) return {};
  const std::string origin = "MANYLIGHTS_SOURCE_DIR=" + std::string(root);
  std::error_code ec;
  if (!std::filesystem::is_directory(root, ec)) throw UserError(origin + ": no such folder");
  for (const char* sub : {"kernels", "gl/shaders", "host/shared"})
    if (!std::filesystem::is_directory(std::filesystem::path(root) / sub, ec))
      throw UserError(origin + ": not a manylights source tree (no " + sub + "/ folder)");
  return root;
}

bool hasEmbeddedFile(std::string_view name) {
  for (const auto& f : embeddedFiles())
    if (name == f.name) return true;
  return false;
}

std::string readEmbeddedFile(std::string_view name) {
  if (const std::string root = sourceDirFromEnv(); !root.empty()) {
    std::ifstream in(diskPath(root, name), std::ios::binary);
    if (in) {
      std::ostringstream ss;
      ss << in.rdbuf();
      return ss.str();
    }
  }
  for (const auto& f : embeddedFiles())
    if (name == f.name) return f.text;
  throw UserError("embedded file '" + std::string(name) + "' not found (was it added to kernels/, host/shared/ or gl/shaders/?)");
}

}  // namespace ml
