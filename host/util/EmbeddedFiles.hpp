#pragma once
// Text files compiled into the binary (kernels/**.cl, host/shared/*.h, gl/shaders/**),
// keyed by the path under their layer's root: "kernels/<feature>/<name>",
// "shared/<name>", "shaders/<feature>/<name>" (cmake/embed_files.cmake). Setting the environment
// variable MANYLIGHTS_SOURCE_DIR=<repo> makes lookups read the files from disk
// instead, so kernels and shaders can be edited without rebuilding; a file the
// tree lacks falls back to the embedded copy. A value that is not a manylights
// source tree (missing, or without kernels/, gl/shaders/ and host/shared/) is a
// UserError naming the variable, not a silent fallback.
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

// The validated $MANYLIGHTS_SOURCE_DIR, or empty when it is unset or empty;
// throws UserError for an unusable value (called at start-up and per lookup).
std::string sourceDirFromEnv();

}  // namespace ml
