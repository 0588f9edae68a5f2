// Scenes shared by the benchmarks.
#pragma once

#include <string>

#include "core/scene.h"

namespace ssgi {

// A scene to draw, or why it could not be built.
struct BenchScene {
  Scene scene;
  std::string error;
};

// data/default.json, loaded once; a missing or malformed file becomes the error every benchmark that
// needs it reports.
const BenchScene& DefaultBenchScene();

}  // namespace ssgi
