#include "support/BruteReference.hpp"

#include <map>

#include "host/assign/BruteForceAssigner.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml::test {

const SceneInputs& referenceScene() {
  static SceneInputs s = [] {
    SceneInputArgs a;
    a.lights = "1024";
    return loadSceneInputs(a);
  }();
  return s;
}

const BruteReference& bruteReference(Pipeline pipeline) {
  static std::map<Pipeline, BruteReference> cache;
  if (auto it = cache.find(pipeline); it != cache.end()) return it->second;
  glContext();
  FrameRenderer r(runtime(), referenceScene().scene, kReferenceWidth, kReferenceHeight);
  r.setLights(referenceScene().lights);
  BruteForceAssigner brute;
  BruteReference ref;
  ref.result = r.render(referenceScene().cameras.frames.front(), brute, {pipeline, true});
  ref.image = r.targets().readColor();
  return cache.emplace(pipeline, std::move(ref)).first->second;
}

}  // namespace ml::test
