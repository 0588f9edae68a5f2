// Colour encodings shared by textures, the G-buffer and image output (DESIGN.md §2: linear HDR
// inside, sRGB-encoded albedo textures and 8-bit outputs). 8-bit conversions go through tables
// built once, so every caller and every SIMD target gets the same bits without calling pow.
#pragma once

#include <algorithm>
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
// the number of the 255 code boundaries at or below x, so the result does not depend on pow's
// rounding.
// Values below 0 (and NaN) give 0, above 1 give 255.
uint8_t LinearToSrgbCode(float linear);

// The table behind LinearToSrgbCode, for SIMD kernels that must give the same codes with one
// gather. With b = clamp(bits(x), kSrgbEncodeLowBits, kSrgbEncodeHighBits) and
// e = entries[(b - kSrgbEncodeLowBits) >> kSrgbEncodeShift]:
//   code = (e & 0xFF) + ((b & kSrgbEncodeOffsetMask) >= (e >> 8)).
// A bucket (2^kSrgbEncodeShift consecutive floats) holds at most one code boundary; the entry packs
// the code of the bucket's smallest float and the boundary's position inside the bucket
// (2^kSrgbEncodeShift, never reached, when there is none). Valid for x >= 0 and not NaN.
inline constexpr int kSrgbEncodeShift = 16;
inline constexpr int32_t kSrgbEncodeLowBits = 0x39000000;   // 2^-13, below the first boundary
inline constexpr int32_t kSrgbEncodeHighBits = 0x3F7FFFFF;  // the largest float below 1
inline constexpr int32_t kSrgbEncodeOffsetMask = (1 << kSrgbEncodeShift) - 1;
const int32_t* SrgbEncodeTableForKernels();

// The largest half float. The frame's radiance buffers (direct light, the colour pyramid, the
// cone-traced reflection) hold finite values in [0, kMaxRadiance]: they fit a GPU port's half-float
// targets, and no NaN or infinity can spread through a blur. Sanitised: NaN and negatives (-inf
// too) -> 0, values above the cap (+inf too) -> the cap: a blown-out pixel stays bright, and the
// pyramid's weighted sums cannot overflow to +inf.
inline constexpr float kMaxRadiance = 65504.0f;
inline float SanitizeRadiance(float v) { return v > 0.0f ? std::min(v, kMaxRadiance) : 0.0f; }

// Unsigned normalised 8-bit code of a value in [0, 1], round half up; out-of-range values clamp,
// NaN gives 0.
uint8_t UnormCode8(float value);

}  // namespace ssgi
