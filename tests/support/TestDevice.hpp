#pragma once
// The OpenCL runtime shared by all tests of one process (created on first use,
// honouring $MANYLIGHTS_DEVICE), and a per-test random seed that is printed on
// failure so a failing random input can be replayed with MANYLIGHTS_TEST_SEED.
#include <cstdint>

#include "host/cl/ClRuntime.hpp"

namespace ml::test {

ClRuntime& runtime();
// Fresh seed per call unless MANYLIGHTS_TEST_SEED is set; recorded as a gtest
// property and in the failure message via SCOPED_TRACE at the call site.
std::uint64_t freshSeed();

}  // namespace ml::test
