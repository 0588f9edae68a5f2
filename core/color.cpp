#include "core/color.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <vector>

namespace ssgi {
namespace {

// The encoder's bucket range: 2^-13, below the first boundary, to the largest float below 1.
constexpr int32_t kSrgbEncodeLowBits = 0x39000000;
constexpr int32_t kSrgbEncodeHighBits = 0x3F7FFFFF;
constexpr int32_t kBucketFloats = int32_t(1) << kCodeBucketShift;
constexpr int32_t kNoBoundary = kBucketFloats;  // an offset no float inside the bucket reaches

struct SrgbTables {
  std::array<float, 256> codeToLinear;
  std::array<float, 255> thresholds;  // thresholds[k]: the linear value where code k rounds up to k + 1
  CodeBuckets encode;

  SrgbTables() {
    for (int k = 0; k < 256; ++k) codeToLinear[k] = SrgbToLinear(float(k) / 255.0f);
    for (int k = 0; k < 255; ++k) thresholds[k] = SrgbToLinear((float(k) + 0.5f) / 255.0f);
    // Over that range, buckets of 2^16 floats are narrower than the gap between two neighbouring
    // boundaries.
    encode = MakeCodeBuckets(thresholds.data(), kSrgbEncodeLowBits, kSrgbEncodeHighBits);
  }
};

// Built during static initialisation: lookups need no thread-safe-static guard. No other static
// initialiser uses these functions.
const SrgbTables kTables;

const SrgbTables& Tables() { return kTables; }

}  // namespace

CodeBuckets MakeCodeBuckets(const float* boundaries, int32_t lowBits, int32_t highBits) {
  const float* const end = boundaries + 255;
  // Below lowBits everything must give 0, and from highBits on 255.
  if (std::bit_cast<int32_t>(boundaries[0]) <= lowBits || std::bit_cast<int32_t>(end[-1]) > highBits) std::abort();
  CodeBuckets buckets;
  buckets.lowBits = lowBits;
  buckets.highBits = highBits;
  buckets.entries.resize(size_t((highBits - lowBits) >> kCodeBucketShift) + 1);
  for (size_t b = 0; b < buckets.entries.size(); ++b) {
    const int32_t first = lowBits + int32_t(b) * kBucketFloats;
    const float* above = std::upper_bound(boundaries, end, std::bit_cast<float>(first));
    int32_t offset = kNoBoundary;
    if (above != end && std::bit_cast<int32_t>(*above) - first < kBucketFloats) {
      offset = std::bit_cast<int32_t>(*above) - first;
      // A second boundary in the same bucket would need a second compare.
      if (above + 1 != end && std::bit_cast<int32_t>(above[1]) - first < kBucketFloats) std::abort();
    }
    buckets.entries[b] = (int32_t(above - boundaries) + 1) << kCodeEntryCodeShift | offset;
  }
  return buckets;
}

float SrgbToLinear(float encoded) {
  return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

float LinearToSrgb(float linear) {
  return linear <= 0.0031308f ? linear * 12.92f : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

const CodeBuckets& SrgbEncodeBuckets() { return Tables().encode; }

const float* SrgbEncodeThresholds() { return Tables().thresholds.data(); }

float SrgbCodeToLinear(uint8_t code) { return Tables().codeToLinear[code]; }

const float* SrgbDecodeTableForKernels() { return Tables().codeToLinear.data(); }

uint8_t LinearToSrgbCode(float linear) {
  if (!(linear > 0.0f)) return 0;
  return BucketCode(Tables().encode, std::bit_cast<int32_t>(linear));
}

uint8_t UnormCode8(float value) {
  if (!(value > 0.0f)) return 0;
  if (value >= 1.0f) return 255;
  return uint8_t(value * 255.0f + 0.5f);
}

}  // namespace ssgi
