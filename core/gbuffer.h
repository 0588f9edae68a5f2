// The packed 128-bit G-buffer (docs/design.md §3, docs/pipeline.md §G-buffer): four 32-bit words per
// pixel, stored as four planes (one per word) so streaming passes load only the words they need.
//
// word 0: bits 0-7 / 8-15 / 16-23 albedo R / G / B (8-bit sRGB codes), bits 24-31 metallic (unorm8)
// word 1: bits 0-23 view-space unit normal (NormalEncoding), bits 24-31 perceptual roughness (unorm8)
// word 2: view depth d = -z_view in metres as float32; background (no geometry) is +infinity
// word 3: shadow term: bit 31 hard-shadow flag (1 = the shadow map says occluded), bits 0-30 the
//         float32 bits of the average blocker distance in metres (>= 0; 0 = no blocker found, lit)
#pragma once

#include <cstdint>
#include <cstring>
#include <limits>

#include <glm/glm.hpp>

#include "core/plane.h"
#include "core/render_modes.h"

namespace ssgi {

inline constexpr float kBackgroundDepth = std::numeric_limits<float>::infinity();
inline constexpr uint32_t kShadowLit = 0u;  // word 3 of a pixel with no blocker

// The four words by what they hold: the indices of GBuffer::word, and the "gbuffer.wordN" dump layers.
struct GBufferWord {
  enum : int { kAlbedoMetallic = 0, kNormalRoughness = 1, kDepth = 2, kShadowTerm = 3 };
};

struct GBuffer {
  Plane<uint32_t> word[4];
  // How word 1 stores the normal: set by the G-buffer pass, read by every pass that decodes it.
  NormalEncoding normalEncoding = NormalEncoding::kOct24;
  int width() const { return int(word[GBufferWord::kAlbedoMetallic].xsize()); }
  int height() const { return int(word[GBufferWord::kAlbedoMetallic].ysize()); }
};

// A G-buffer of the given size and normal encoding, every pixel background: words 0, 1, 3 zero,
// depth +infinity.
GBuffer MakeGBuffer(int width, int height, NormalEncoding encoding);

uint32_t PackAlbedoMetallic(glm::vec3 linearAlbedo, float metallic);
glm::vec3 UnpackAlbedo(uint32_t word0);  // linear
float UnpackMetallic(uint32_t word0);

// 24-bit normal codes. xyz8: each component as unorm8 of n * 0.5 + 0.5 (the paper's layout).
// oct24: octahedral map (Cigolle et al. 2014) with 12 bits per axis, u in bits 0-11, v in 12-23.
uint32_t EncodeNormal(glm::vec3 unitNormal, NormalEncoding encoding);
glm::vec3 DecodeNormal(uint32_t code24, NormalEncoding encoding);  // unit length

uint32_t PackNormalRoughness(glm::vec3 unitNormal, float roughness, NormalEncoding encoding);
// The unit view-space normal of word 1 (its low 24 bits).
inline glm::vec3 UnpackNormal(uint32_t word1, NormalEncoding encoding) {
  return DecodeNormal(word1 & 0xFFFFFFu, encoding);
}
float UnpackRoughness(uint32_t word1);

inline uint32_t PackDepth(float viewDepth) {
  uint32_t bits;
  std::memcpy(&bits, &viewDepth, 4);
  return bits;
}
inline float UnpackDepth(uint32_t word2) {
  float depth;
  std::memcpy(&depth, &word2, 4);
  return depth;
}

uint32_t PackShadowTerm(bool hardShadow, float averageBlockerDistance);
inline bool UnpackHardShadow(uint32_t word3) { return (word3 >> 31) != 0; }
float UnpackBlockerDistance(uint32_t word3);

}  // namespace ssgi
