// Tonemap pass (DESIGN.md §8, docs/pipeline.md §Tonemap): linear HDR radiance -> 8-bit sRGB.
// colour * 2^exposureEv, then per channel either the ACES filmic curve fitted by Narkowicz (2015),
// x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), or a plain clamp, then clamped to [0, 1] and
// encoded to the nearest 8-bit sRGB code (core/color.h). NaN encodes as 0.
#pragma once

#include <cstdint>
#include <vector>

#include "core/plane.h"
#include "core/scene.h"

namespace ssgi {

struct TonemapParams {
  float exposureEv = 0.0f;
  Tonemap curve = Tonemap::kAces;
};

struct TonemapOutputs {
  std::vector<uint8_t> rgb;  // interleaved R, G, B rows, top row first, width * height * 3 bytes
};

float TonemapCurve(float x, Tonemap curve);

void RunTonemap(const Plane3<float>& radiance, const TonemapParams& params, TonemapOutputs& out);

}  // namespace ssgi
