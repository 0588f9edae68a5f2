#include "passes/tonemap.h"

#include <algorithm>
#include <cmath>

#include "core/color.h"
#include "core/parallel.h"

namespace ssgi {

float TonemapCurve(float x, Tonemap curve) {
  if (curve == Tonemap::kAces) x = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
  return std::clamp(x, 0.0f, 1.0f);
}

void RunTonemap(const Plane3<float>& radiance, const TonemapParams& params, TonemapOutputs& out) {
  const size_t width = radiance.c[0].xsize(), height = radiance.c[0].ysize();
  const float scale = std::exp2(params.exposureEv);
  out.rgb.assign(width * height * 3, 0);
  ParallelFor("tonemap", height, [&](size_t y) {
    uint8_t* row = out.rgb.data() + y * width * 3;
    for (int c = 0; c < 3; ++c) {
      const float* in = radiance.c[c].ConstRow(y);
      for (size_t x = 0; x < width; ++x) {
        const float v = in[x] * scale;
        row[3 * x + c] = LinearToSrgbCode(std::isnan(v) ? 0.0f : TonemapCurve(std::max(v, 0.0f), params.curve));
      }
    }
  });
}

}  // namespace ssgi
