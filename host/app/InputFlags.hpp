#pragma once
// The flags that say what a run renders and where, added in one place for
// render, view, bench and compare-reference, so that each has the same name,
// help and check everywhere. A command picks the groups it takes:
//   addInputFlags(*cmd, {kSceneFlags | kDeviceFlag, &a.inputs, &a.device});
#include <CLI/CLI.hpp>

#include <string>

#include "host/run/SceneInputs.hpp"

namespace ml {

enum InputFlagGroup : unsigned {
  kSceneFlag = 1u << 0,       // --scene (also --suite), --camera, --light-threshold
  kLightFlag = 1u << 1,       // --lights: one count, JSON or glTF file (render, view)
  kGenerateFlags = 1u << 2,   // --light-volumes, --light-radius, --light-density, --seed
  kSuiteFlags = 1u << 3,      // --geometry, --allow-missing-meshes
  kDeviceFlag = 1u << 4,      // --device
  kProgressFlag = 1u << 5,    // --progress
  kWriteLightsFlag = 1u << 6, // --write-lights (render, bench)
  kSceneInputFlags = kSceneFlag | kLightFlag | kGenerateFlags,
};

struct InputFlags {
  unsigned groups = 0;
  SceneInputArgs* inputs = nullptr;  // kSceneFlag, kLightFlag, kGenerateFlags, kSuiteFlags
  std::string* device = nullptr;     // kDeviceFlag
  std::string* progress = nullptr;   // kProgressFlag
};

void addInputFlags(CLI::App& cmd, const InputFlags& f);

}  // namespace ml
