// Tonemap pass (docs/design.md §8, docs/pipeline.md §Tonemap): linear HDR radiance -> 8-bit sRGB.
// colour * 2^exposureEv, then per channel either the ACES filmic curve fitted by Narkowicz (2015),
// x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), or a plain clamp, then clamped to [0, 1] and
// encoded to the nearest 8-bit sRGB code (core/color.h): as a count of the code boundaries at or
// below x (TonemapCode). NaN encodes as 0; inputs are capped at kTonemapMaxInput, so +inf encodes
// as white.
// The per-row kernel has a scalar definition (tonemap.cpp) and a Highway twin (tonemap_simd.cpp)
// that gives the same bytes on every SIMD target.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/color.h"
#include "core/kernel_path.h"
#include "core/plane.h"
#include "core/render_modes.h"

namespace ssgi {

inline constexpr float kTonemapMaxInput = 65504.0f;  // the largest half float: far past white

struct TonemapParams {
  float exposureEv = 0.0f;
  Tonemap curve = Tonemap::kAces;
};

struct TonemapOutputs {
  std::vector<uint8_t> rgb;  // interleaved R, G, B rows, top row first, width * height * 3 bytes
};

struct TonemapStats {
  double ms = 0.0;
  size_t pixels = 0;
};

// Reuses out.rgb's memory when it already has the size. kernels: which definition of the row kernel
// runs (the same bytes either way).
TonemapStats RunTonemap(const Plane3<float>& radiance, const TonemapParams& params, TonemapOutputs& out,
                        KernelPath kernels = KernelPath::kSimd);

// The ACES filmic curve fitted by Narkowicz (2015), in double precision: non-decreasing over the
// floats, so its code boundaries are unique.
double AcesCurve(double x);

// The code of one channel's value x, already times the exposure scale: the definition. NaN and
// x <= 0 give 0; x is capped at kTonemapMaxInput; then the number of the curve's 255 code
// boundaries at or below x, through TonemapCodeBuckets. For kClamp the boundaries are the sRGB
// encoder's thresholds (LinearToSrgbCode(min(x, 1))); for kAces the smallest float where
// AcesCurve(x) reaches each threshold.
uint8_t TonemapCode(float x, Tonemap curve);

// The bucket tables (core/color.h) behind TonemapCode, one per curve, built once: the SIMD kernel
// reads them with one lookup per channel (mostly in registers, GatherNearIndex3) and needs neither
// the curve's division nor a clamp.
const CodeBuckets& TonemapCodeBuckets(Tonemap curve);

// One row: rgb[3 i + c] = sRGB code of the tonemapped radiance[c][i] * scale.
void TonemapRowScalar(const float* const radiance[3], size_t count, float scale, Tonemap curve, uint8_t* rgb);
void TonemapRowSimd(const float* const radiance[3], size_t count, float scale, Tonemap curve, uint8_t* rgb);

}  // namespace ssgi
