#pragma once
// What a run renders (SceneInputArgs, loadSceneInputs) is resolved in one
// place with the benchmark's scenes and light sets: host/bench/BenchInputs.hpp.
// This header stays for the commands and tests that include it by this name.
#include "host/bench/BenchInputs.hpp"
