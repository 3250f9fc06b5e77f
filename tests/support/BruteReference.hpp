#pragma once
// The scene and brute-force reference frames that the technique render tests
// compare against: the default scene with 1,024 generated lights, its first
// camera frame, at kReferenceWidth x kReferenceHeight with counts on. Loaded
// and rendered once per test process (per pipeline), shared by every suite.
#include <vector>

#include "gl/FrameRenderer.hpp"
#include "host/app/SceneInputs.hpp"

namespace ml::test {

constexpr unsigned kReferenceWidth = 320, kReferenceHeight = 180;

const SceneInputs& referenceScene();

struct BruteReference {
  std::vector<float> image;
  FrameResult result;
};
const BruteReference& bruteReference(Pipeline pipeline);

}  // namespace ml::test
