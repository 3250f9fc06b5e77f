#pragma once
// Text files compiled into the binary (kernels/*.cl, host/shared/*.h, gl/shaders/*),
// keyed "kernels/<name>", "shared/<name>", "shaders/<name>". Setting the environment
// variable MANYLIGHTS_SOURCE_DIR=<repo> makes lookups read the files from disk
// instead, so kernels and shaders can be edited without rebuilding.
#include <string>
#include <string_view>
#include <vector>

namespace ml {

struct EmbeddedFile {
  const char* name;
  const char* text;
};

const std::vector<EmbeddedFile>& embeddedFiles();

// Returns the file's text; throws UserError naming the file if it does not exist.
std::string readEmbeddedFile(std::string_view name);
bool hasEmbeddedFile(std::string_view name);

}  // namespace ml
