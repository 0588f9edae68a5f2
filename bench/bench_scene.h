// Scenes shared by the benchmarks.
#pragma once

#include <string>

#include "core/scene.h"
#include "passes/frame.h"
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

// One whole frame of the default scene at size x size, rendered once per size: its buffers are the
// inputs of the benchmarks of single passes.
const Frame& DefaultBenchFrame(int size);

}  // namespace ssgi
