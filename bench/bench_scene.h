// Scenes shared by the benchmarks.
#pragma once

#include <string>

#include "core/scene.h"
#include "passes/frame_config.h"

namespace ssgi {

// A scene to draw, or why it could not be built.
struct BenchScene {
  Scene scene;
  FrameConfig config;  // the scene file's render block
  std::string error;
};

// data/default.json with its frame configuration, loaded once; a missing or malformed file becomes the error every benchmark that
// needs it reports.
const BenchScene& DefaultBenchScene();

}  // namespace ssgi
