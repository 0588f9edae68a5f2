// Colour encodings shared by textures, the G-buffer and image output (docs/design.md §2: linear HDR
// inside, sRGB-encoded albedo textures and 8-bit outputs). 8-bit conversions go through tables
// built once, so every caller and every SIMD target gets the same bits without calling pow.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

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

// A non-decreasing map from floats to 8-bit codes as a table that SIMD kernels read with one gather:
// code(x) = the number of the 255 increasing `boundaries` at or below x. With
// b = clamp(bits(x), lowBits, highBits) and e = entries[(b - lowBits) >> kCodeBucketShift]:
//   code = (e >> kCodeEntryCodeShift) - ((b & kCodeBucketOffsetMask) < (e & kCodeEntryOffsetMask)).
// Positive floats order like their bit patterns. A bucket (2^kCodeBucketShift consecutive floats)
// holds at most one boundary (checked as the table is built); the entry packs one more than the code
// of the bucket's smallest float (bits 17 and up) and the boundary's position inside it (bits 0-16;
// 2^kCodeBucketShift, never reached, when there is none), so a kernel subtracts the comparison's
// sign instead of turning a mask into a vector. Exact for x >= 0 and not NaN when lowBits lies below
// the first boundary (negative floats clamp to it: code 0) and highBits at or above the last (code
// 255 from there).
inline constexpr int kCodeBucketShift = 16;
inline constexpr int32_t kCodeBucketOffsetMask = (1 << kCodeBucketShift) - 1;
inline constexpr int kCodeEntryCodeShift = kCodeBucketShift + 1;
inline constexpr int32_t kCodeEntryOffsetMask = (1 << kCodeEntryCodeShift) - 1;
struct CodeBuckets {
  std::vector<int32_t> entries;  // 32-bit so SIMD kernels can gather them
  int32_t lowBits = 0, highBits = 0;
};
CodeBuckets MakeCodeBuckets(const float* boundaries, int32_t lowBits, int32_t highBits);
inline uint8_t BucketCode(const CodeBuckets& buckets, int32_t bits) {
  bits = std::min(std::max(bits, buckets.lowBits), buckets.highBits);
  const int32_t entry = buckets.entries[size_t((bits - buckets.lowBits) >> kCodeBucketShift)];
  return uint8_t((entry >> kCodeEntryCodeShift) - ((bits & kCodeBucketOffsetMask) < (entry & kCodeEntryOffsetMask)));
}

// The buckets behind LinearToSrgbCode (boundaries: the linear values halfway between codes in
// encoded space), from 2^-13 (below the first boundary) to the largest float below 1.
const CodeBuckets& SrgbEncodeBuckets();
// Its boundaries: thresholds[k] = SrgbToLinear((k + 0.5) / 255), k = 0..254, where code k rounds up
// to k + 1.
const float* SrgbEncodeThresholds();

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
