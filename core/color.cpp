#include "core/color.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace ssgi {
namespace {

// Positive floats below 1 have bit patterns below 0x3F800000; their top 17 bits (exponent and 8
// mantissa bits) pick a bucket no wider than 1/256 of its value, which holds at most two code
// boundaries. The bucket's table entry is the code of its smallest value; a lookup then steps over
// the thresholds inside the bucket. Exact, and with at most two data-dependent steps.
constexpr int kBucketShift = kSrgbBucketShift;
constexpr uint32_t kOneBits = 0x3F800000u;

struct SrgbTables {
  std::array<float, 256> codeToLinear;
  std::array<float, 256> thresholds;  // thresholds[k]: linear value where code k rounds up to k + 1; [255] = inf
  std::vector<int32_t> bucketCode;  // 32-bit so SIMD kernels can gather it
  SrgbEncodeTables forKernels;

  SrgbTables() : bucketCode(kOneBits >> kBucketShift) {
    for (int k = 0; k < 256; ++k) codeToLinear[k] = SrgbToLinear(float(k) / 255.0f);
    for (int k = 0; k < 255; ++k) thresholds[k] = SrgbToLinear((float(k) + 0.5f) / 255.0f);
    thresholds[255] = std::numeric_limits<float>::infinity();
    for (uint32_t b = 0; b < bucketCode.size(); ++b) {
      float lowest;
      const uint32_t bits = b << kBucketShift;
      std::memcpy(&lowest, &bits, 4);
      bucketCode[b] = int32_t(std::upper_bound(thresholds.begin(), thresholds.end() - 1, lowest) - thresholds.begin());
    }
    forKernels = {bucketCode.data(), thresholds.data()};
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

const SrgbEncodeTables& SrgbEncodeTablesForKernels() { return Tables().forKernels; }

float SrgbCodeToLinear(uint8_t code) { return Tables().codeToLinear[code]; }

const float* SrgbDecodeTableForKernels() { return Tables().codeToLinear.data(); }

uint8_t LinearToSrgbCode(float linear) {
  if (!(linear > 0.0f)) return 0;
  if (linear >= 1.0f) return 255;
  const SrgbTables& tables = Tables();
  uint32_t bits;
  std::memcpy(&bits, &linear, 4);
  unsigned code = unsigned(tables.bucketCode[bits >> kBucketShift]);
  code += linear >= tables.thresholds[code];
  code += linear >= tables.thresholds[code];
  return uint8_t(code);
}

uint8_t UnormCode8(float value) {
  if (!(value > 0.0f)) return 0;
  if (value >= 1.0f) return 255;
  return uint8_t(value * 255.0f + 0.5f);
}

}  // namespace ssgi
