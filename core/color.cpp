#include "core/color.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <vector>

namespace ssgi {
namespace {

// Positive floats order like their bit patterns. From 2^-13 (below the first code boundary, about
// 1.5e-4) to 1, buckets of 2^16 consecutive floats are narrower than the gap between two
// neighbouring boundaries, so each holds at most one (checked as the table is built); its entry
// gives the code of its smallest float and where inside it the boundary lies. One lookup and one
// compare, exact.
constexpr int32_t kBucketFloats = int32_t(1) << kSrgbEncodeShift;
constexpr int32_t kNoBoundary = kBucketFloats;  // an offset no float inside the bucket reaches

struct SrgbTables {
  std::array<float, 256> codeToLinear;
  std::array<float, 255> thresholds;  // thresholds[k]: the linear value where code k rounds up to k + 1
  std::vector<int32_t> encode;  // 32-bit so SIMD kernels can gather it

  SrgbTables() : encode(size_t((kSrgbEncodeHighBits - kSrgbEncodeLowBits) >> kSrgbEncodeShift) + 1) {
    for (int k = 0; k < 256; ++k) codeToLinear[k] = SrgbToLinear(float(k) / 255.0f);
    for (int k = 0; k < 255; ++k) thresholds[k] = SrgbToLinear((float(k) + 0.5f) / 255.0f);
    for (size_t b = 0; b < encode.size(); ++b) {
      const int32_t first = kSrgbEncodeLowBits + int32_t(b) * kBucketFloats;
      const auto above = std::upper_bound(thresholds.begin(), thresholds.end(), std::bit_cast<float>(first));
      int32_t offset = kNoBoundary;
      if (above != thresholds.end() && std::bit_cast<int32_t>(*above) - first < kBucketFloats) {
        offset = std::bit_cast<int32_t>(*above) - first;
        // A second boundary in the same bucket would need a second compare.
        if (above + 1 != thresholds.end() && std::bit_cast<int32_t>(above[1]) - first < kBucketFloats) std::abort();
      }
      encode[b] = offset << 8 | int32_t(above - thresholds.begin());
    }
    // Everything below the first bucket must encode to 0.
    if (std::bit_cast<int32_t>(thresholds[0]) <= kSrgbEncodeLowBits) std::abort();
  }
};

// Built during static initialisation: lookups need no thread-safe-static guard. No other static
// initialiser uses these functions.
const SrgbTables kTables;

const SrgbTables& Tables() { return kTables; }

}  // namespace

float SrgbToLinear(float encoded) {
  return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

float LinearToSrgb(float linear) {
  return linear <= 0.0031308f ? linear * 12.92f : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

const int32_t* SrgbEncodeTableForKernels() { return Tables().encode.data(); }

float SrgbCodeToLinear(uint8_t code) { return Tables().codeToLinear[code]; }

const float* SrgbDecodeTableForKernels() { return Tables().codeToLinear.data(); }

uint8_t LinearToSrgbCode(float linear) {
  if (!(linear > 0.0f)) return 0;
  const int32_t bits = std::min(std::max(std::bit_cast<int32_t>(linear), kSrgbEncodeLowBits), kSrgbEncodeHighBits);
  const int32_t entry = Tables().encode[size_t((bits - kSrgbEncodeLowBits) >> kSrgbEncodeShift)];
  return uint8_t((entry & 0xFF) + ((bits & kSrgbEncodeOffsetMask) >= (entry >> 8)));
}

uint8_t UnormCode8(float value) {
  if (!(value > 0.0f)) return 0;
  if (value >= 1.0f) return 255;
  return uint8_t(value * 255.0f + 0.5f);
}

}  // namespace ssgi
