#pragma once
// Where the project's data/ folder is: $MANYLIGHTS_DATA_DIR, else <exe>/../data
// (the build tree or an install), else the source tree's data/ recorded at
// build time. Returns the first that exists.
#include <string>

namespace ml {
std::string dataDir();
std::string dataPath(const std::string& relative);  // dataDir() + "/" + relative
}  // namespace ml
