#include "core/color.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace ssgi {
namespace {

struct SrgbTables {
  std::array<float, 256> codeToLinear;
  std::array<float, 255> thresholds;  // linear value where code k rounds up to k + 1

  SrgbTables() {
    for (int k = 0; k < 256; ++k) codeToLinear[k] = SrgbToLinear(float(k) / 255.0f);
    for (int k = 0; k < 255; ++k) thresholds[k] = SrgbToLinear((float(k) + 0.5f) / 255.0f);
  }
};

const SrgbTables& Tables() {
  static const SrgbTables tables;
  return tables;
}

}  // namespace

float SrgbToLinear(float encoded) {
  return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

float LinearToSrgb(float linear) {
  return linear <= 0.0031308f ? linear * 12.92f : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

float SrgbCodeToLinear(uint8_t code) { return Tables().codeToLinear[code]; }

uint8_t LinearToSrgbCode(float linear) {
  if (!(linear > 0.0f)) return 0;
  const auto& t = Tables().thresholds;
  return uint8_t(std::upper_bound(t.begin(), t.end(), linear) - t.begin());
}

uint8_t UnormCode8(float value) {
  if (!(value > 0.0f)) return 0;
  if (value >= 1.0f) return 255;
  return uint8_t(value * 255.0f + 0.5f);
}

}  // namespace ssgi
