#include "support/TestSizes.hpp"

#include <cstdlib>
#include <string_view>

namespace ml::test {

bool smallSizes() {
  static const bool small = [] {
    const char* env = std::getenv("MANYLIGHTS_TEST_SMALL");
    return env && *env && std::string_view(env) != "0";
  }();
  return small;
}

std::vector<std::size_t> sizesUpToLimit(std::initializer_list<std::size_t> sizes) {
  std::vector<std::size_t> out;
  for (const std::size_t n : sizes)
    if (!smallSizes() || n <= kSmallLimit) out.push_back(n);
  return out;
}

}  // namespace ml::test
