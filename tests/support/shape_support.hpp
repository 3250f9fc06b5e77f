#pragma once
// Kernel shapes for the technique tests (tiled, clustered): every kernel test
// runs in both shapes, CpuChunked and GpuWorkGroup, on whatever device the
// tests use. MANYLIGHTS_TEST_SMALL=1 keeps only small inputs (for running the
// GPU shapes under a simulator such as Oclgrind, ~100x slower than PoCL).
// GPU-shape tests carry "gpu" in their names: --gtest_filter='*gpu*'.
#include <cstdlib>
#include <cstring>
#include <string>

#include "host/cl/KernelLimits.hpp"

namespace ml::test {

inline bool smallTests() {
  const char* v = std::getenv("MANYLIGHTS_TEST_SMALL");
  return v && *v && std::strcmp(v, "0") != 0;
}

inline std::string shapeLabel(KernelShape s) { return kernelShapeName(s); }
// "" for Auto, else "_cpu" / "_gpu": a test-name suffix.
inline std::string shapeSuffix(KernelShape s) {
  std::string r;
  if (s != KernelShape::Auto) r.append("_").append(kernelShapeName(s));
  return r;
}

constexpr KernelShape kBothShapes[] = {KernelShape::CpuChunked, KernelShape::GpuWorkGroup};

}  // namespace ml::test
