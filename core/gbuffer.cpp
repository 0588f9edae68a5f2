#include "core/gbuffer.h"

#include <cmath>

#include "core/check.h"
#include "core/color.h"

namespace ssgi {
namespace {

constexpr float kOctMax = 4095.0f;

uint32_t QuantizeSigned(float value, float maxCode) {
  // Comparisons rather than fmin/fmax, which GCC leaves as library calls; NaN maps to -1 as well.
  const float clamped = !(value > -1.0f) ? -1.0f : (value > 1.0f ? 1.0f : value);
  return uint32_t((clamped * 0.5f + 0.5f) * maxCode + 0.5f);
}

float DequantizeSigned(uint32_t code, float maxCode) { return float(code) / maxCode * 2.0f - 1.0f; }

float SignNotZero(float v) { return v >= 0.0f ? 1.0f : -1.0f; }

}  // namespace

GBuffer MakeGBuffer(int width, int height, NormalEncoding encoding) {
  GBuffer g;
  g.normalEncoding = encoding;
  g.word[GBufferWord::kAlbedoMetallic] = MakePlane<uint32_t>(width, height, 0u);
  g.word[GBufferWord::kNormalRoughness] = MakePlane<uint32_t>(width, height, 0u);
  g.word[GBufferWord::kDepth] = MakePlane<uint32_t>(width, height, PackDepth(kBackgroundDepth));
  g.word[GBufferWord::kShadowTerm] = MakePlane<uint32_t>(width, height, kShadowLit);
  return g;
}

uint32_t PackAlbedoMetallic(glm::vec3 linearAlbedo, float metallic) {
  return uint32_t(LinearToSrgbCode(linearAlbedo.x)) | uint32_t(LinearToSrgbCode(linearAlbedo.y)) << 8 |
         uint32_t(LinearToSrgbCode(linearAlbedo.z)) << 16 | uint32_t(UnormCode8(metallic)) << 24;
}

glm::vec3 UnpackAlbedo(uint32_t word0) {
  return {SrgbCodeToLinear(uint8_t(word0)), SrgbCodeToLinear(uint8_t(word0 >> 8)),
          SrgbCodeToLinear(uint8_t(word0 >> 16))};
}

float UnpackMetallic(uint32_t word0) { return float(word0 >> 24) / 255.0f; }

uint32_t EncodeNormal(glm::vec3 n, NormalEncoding encoding) {
  if (encoding == NormalEncoding::kXyz8) {
    return QuantizeSigned(n.x, 255.0f) | QuantizeSigned(n.y, 255.0f) << 8 | QuantizeSigned(n.z, 255.0f) << 16;
  }
  const float l1 = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
  float u = n.x / l1;
  float v = n.y / l1;
  if (n.z < 0.0f) {
    const float foldedU = (1.0f - std::fabs(v)) * SignNotZero(u);
    const float foldedV = (1.0f - std::fabs(u)) * SignNotZero(v);
    u = foldedU;
    v = foldedV;
  }
  return QuantizeSigned(u, kOctMax) | QuantizeSigned(v, kOctMax) << 12;
}

glm::vec3 DecodeNormal(uint32_t code, NormalEncoding encoding) {
  glm::vec3 n;
  if (encoding == NormalEncoding::kXyz8) {
    n = {DequantizeSigned(code & 0xFFu, 255.0f), DequantizeSigned((code >> 8) & 0xFFu, 255.0f),
         DequantizeSigned((code >> 16) & 0xFFu, 255.0f)};
  } else {
    const float u = DequantizeSigned(code & 0xFFFu, kOctMax);
    const float v = DequantizeSigned((code >> 12) & 0xFFFu, kOctMax);
    n = {u, v, 1.0f - std::fabs(u) - std::fabs(v)};
    const float t = std::fmax(-n.z, 0.0f);
    n.x += n.x >= 0.0f ? -t : t;
    n.y += n.y >= 0.0f ? -t : t;
  }
  return n / std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
}

uint32_t PackNormalRoughness(glm::vec3 unitNormal, float roughness, NormalEncoding encoding) {
  return EncodeNormal(unitNormal, encoding) | uint32_t(UnormCode8(roughness)) << 24;
}

float UnpackRoughness(uint32_t word1) { return float(word1 >> 24) / 255.0f; }

uint32_t PackShadowTerm(bool hardShadow, float averageBlockerDistance) {
  SSGI_CHECK(averageBlockerDistance >= 0.0f);
  return PackDepth(averageBlockerDistance) | (hardShadow ? 0x80000000u : 0u);
}

float UnpackBlockerDistance(uint32_t word3) { return UnpackDepth(word3 & 0x7FFFFFFFu); }

}  // namespace ssgi
