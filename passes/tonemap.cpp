#include "passes/tonemap.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "core/color.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi {

double AcesCurve(double x) { return x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14); }

namespace {

// For each code k + 1, the smallest float x in [0, kTonemapMaxInput] whose AcesCurve(x) reaches the
// sRGB encoder's threshold k: bisection over the bit patterns, which order like the floats; the
// curve in double precision is non-decreasing over them (tested), so the boundary is unique.
CodeBuckets MakeAcesCodeBuckets() {
  const int32_t maxBits = std::bit_cast<int32_t>(kTonemapMaxInput);
  const float* thresholds = SrgbEncodeThresholds();
  std::array<float, 255> boundaries;
  for (int k = 0; k < 255; ++k) {
    int32_t below = 0, at = maxBits;  // AcesCurve(below) < threshold <= AcesCurve(at)
    while (at - below > 1) {
      const int32_t middle = below + (at - below) / 2;
      (AcesCurve(std::bit_cast<float>(middle)) >= double(thresholds[k]) ? at : below) = middle;
    }
    boundaries[size_t(k)] = std::bit_cast<float>(at);
  }
  // 2^-11 lies below the first boundary (about 7e-4).
  return MakeCodeBuckets(boundaries.data(), 0x3A000000, maxBits);
}

}  // namespace

const CodeBuckets& TonemapCodeBuckets(Tonemap curve) {
  if (curve == Tonemap::kClamp) return SrgbEncodeBuckets();  // values from 1 on clamp to the last bucket
  static const CodeBuckets aces = MakeAcesCodeBuckets();
  return aces;
}

uint8_t TonemapCode(float x, Tonemap curve) {
  if (!(x > 0.0f)) return 0;  // NaN too
  return BucketCode(TonemapCodeBuckets(curve), std::bit_cast<int32_t>(std::min(x, kTonemapMaxInput)));
}

void TonemapRowScalar(const float* const radiance[3], size_t count, float scale, Tonemap curve, uint8_t* rgb) {
  for (size_t i = 0; i < count; ++i) {
    for (int c = 0; c < 3; ++c) rgb[3 * i + c] = TonemapCode(radiance[c][i] * scale, curve);
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
