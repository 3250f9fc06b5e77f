#include "support/TestDevice.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <memory>
#include <random>

namespace ml::test {

ClRuntime& runtime() {
  // Never destroyed: CL calls from static destructors run after the driver's
  // own exit handlers (Oclgrind's thread-local API state is gone by then: a
  // release at exit corrupted the heap and aborted the process).
  static ClRuntime* rt = ClRuntime::create(DeviceChoice::resolve("")).release();
  return *rt;
}

std::uint64_t freshSeed() {
  std::uint64_t seed;
  if (const char* env = std::getenv("MANYLIGHTS_TEST_SEED"); env && *env) {
    seed = std::strtoull(env, nullptr, 10);
  } else {
    static std::mt19937_64 gen(std::random_device{}() ^
                               static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()));
    seed = gen();
  }
  ::testing::Test::RecordProperty("seed", std::to_string(seed));
  return seed;
}

}  // namespace ml::test
