// Colour encodings shared by textures, the G-buffer and image output (DESIGN.md §2: linear HDR
// inside, sRGB-encoded albedo textures and 8-bit outputs). 8-bit conversions go through tables
// built once, so every caller and every SIMD target gets the same bits without calling pow.
#pragma once

#include <cstdint>

namespace ssgi {

// The exact sRGB transfer functions (IEC 61966-2-1), for values in [0, 1].
float SrgbToLinear(float encoded);
float LinearToSrgb(float linear);

// Linear value of an 8-bit sRGB code.
float SrgbCodeToLinear(uint8_t code);
// The table behind SrgbCodeToLinear (256 entries, indexed by code), for SIMD kernels that gather
// from it and so give the same values.
const float* SrgbDecodeTableForKernels();

// The 8-bit sRGB code nearest in encoded space to a linear value: round(LinearToSrgb(x) * 255),
// found by bisection over the 255 thresholds, so the result does not depend on pow's rounding.
// Values below 0 (and NaN) give 0, above 1 give 255.
uint8_t LinearToSrgbCode(float linear);

// The tables behind LinearToSrgbCode, for SIMD kernels that must give the same codes: for
// 0 < x < 1, code = bucketCode[bits(x) >> kSrgbBucketShift], then twice code += (x >= thresholds[code])
// (a bucket holds at most two code boundaries; thresholds[255] is +inf).
inline constexpr int kSrgbBucketShift = 15;
struct SrgbEncodeTables {
  const int32_t* bucketCode;  // 0x3F800000 >> kSrgbBucketShift entries
  const float* thresholds;    // 256 entries
};
const SrgbEncodeTables& SrgbEncodeTablesForKernels();

// Unsigned normalised 8-bit code of a value in [0, 1], round half up; out-of-range values clamp,
// NaN gives 0.
uint8_t UnormCode8(float value);

}  // namespace ssgi
