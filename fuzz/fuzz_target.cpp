// One libFuzzer harness per entry point of FuzzEntryPoints.hpp, chosen at
// build time (ML_FUZZ_ENTRY, set by fuzz/CMakeLists.txt). A UserError is the
// clean answer to bad input; everything else reaches libFuzzer as a crash.
#include <cstddef>
#include <cstdint>

#include "fuzz/FuzzEntryPoints.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    ML_FUZZ_ENTRY(data, size);
  } catch (const ml::UserError&) {
  }
  return 0;
}
