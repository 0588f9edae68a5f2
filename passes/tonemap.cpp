#include "passes/tonemap.h"

#include <algorithm>
#include <cmath>

#include "core/color.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi {

void TonemapRowScalar(const float* const radiance[3], size_t count, float scale, Tonemap curve, uint8_t* rgb) {
  for (size_t i = 0; i < count; ++i) {
    for (int c = 0; c < 3; ++c) {
      float x = radiance[c][i] * scale;
      x = std::isnan(x) ? 0.0f : std::min(std::max(x, 0.0f), kTonemapMaxInput);
      if (curve == Tonemap::kAces) x = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
      rgb[3 * i + c] = LinearToSrgbCode(std::min(x, 1.0f));
    }
  }
}

TonemapStats RunTonemap(const Plane3<float>& radiance, const TonemapParams& params, TonemapOutputs& out,
                        KernelPath kernels) {
  Stopwatch stopwatch;
  const size_t width = radiance.c[0].xsize(), height = radiance.c[0].ysize();
  const float scale = std::exp2(params.exposureEv);
  // Every byte is written below, so a kept buffer needs no clearing.
  out.rgb.resize(width * height * 3);
  const auto tonemapRow = kernels == KernelPath::kSimd ? TonemapRowSimd : TonemapRowScalar;
  ParallelForRowBands("tonemap", height, [&](size_t, size_t yBegin, size_t yEnd) {
    for (size_t y = yBegin; y < yEnd; ++y) {
      const float* const rows[3] = {radiance.c[0].ConstRow(y), radiance.c[1].ConstRow(y), radiance.c[2].ConstRow(y)};
      tonemapRow(rows, width, scale, params.curve, out.rgb.data() + y * width * 3);
    }
  });
  return {stopwatch.Lap(), width * height};
}

}  // namespace ssgi
