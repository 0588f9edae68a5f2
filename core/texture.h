// Mip-mapped textures, read by OpenImageIO (docs/design.md §4), or decoded by the glTF loader.
// Texels are kept as 8 bits per channel, four channels (RGBA), with a full mip chain down to 1x1
// built from the linear values. Colour textures (map_Kd) are sRGB-encoded and decoded to linear
// before filtering; data textures (map_Pm, map_Pr, map_d) are linear. Addressing repeats (OBJ UVs
// outside [0, 1] tile) unless a glTF sampler clamps or mirrors; v = 0 is the bottom row of the
// image (OBJ convention).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/glm.hpp>

namespace ssgi {

enum class TextureEncoding : uint8_t { kSrgb, kLinear };

// Addressing outside [0, 1], per axis (glTF's sampler wrapS and wrapT; OBJ textures repeat).
// kClamp and kMirror differ from kRepeat in the coordinate (clamped to [0, 1], or mirrored every
// other repeat); both read the edge texel beyond an edge, where kRepeat reads the other side's.
enum class TextureWrap : int32_t { kRepeat, kClamp, kMirror };

struct TextureLevel {
  int width = 0;
  int height = 0;
  size_t offset = 0;  // its first texel's index in Texture::texels
};

struct Texture {
  TextureEncoding encoding = TextureEncoding::kLinear;
  TextureWrap wrapU = TextureWrap::kRepeat, wrapV = TextureWrap::kRepeat;
  int sourceChannels = 4;             // channels in the file (1 = grey, 3 = RGB, 4 = RGBA)
  std::vector<TextureLevel> levels;   // levels[0] is full size, the last is 1x1
  // Every level's texels, level after level, each row-major, top row first; a texel is 4 bytes,
  // R, G, B, A (one 32-bit word, R in its low byte, for a SIMD gather).
  std::vector<uint8_t> texels;

  // The first byte of a level's texels.
  const uint8_t* Texels(const TextureLevel& level) const { return texels.data() + 4 * level.offset; }
};

// Reads an image file into a texture with its mip chain. Throws InputError naming the file when it
// is missing or unreadable, or a side is longer than kMaxTextureSide. Grey images are replicated to RGB; missing alpha reads as 1.
Texture LoadTexture(const std::filesystem::path& file, TextureEncoding encoding);

// Builds a texture from 8-bit RGBA texels (top row first); used by tests and procedural content.
Texture MakeTexture(int width, int height, std::vector<uint8_t> rgba, TextureEncoding encoding);

// What a SIMD kernel reads of a texture (core/texture-inl.h's SampleTextureV): flat arrays.
inline constexpr int kMaxTextureLevels = 16;
// The longest side a texture may have: its mip chain has at most kMaxTextureLevels levels (LoadTexture
// refuses a larger image; 32768 x 32768 texels with their mips still index in 32 bits).
inline constexpr int kMaxTextureSide = 1 << (kMaxTextureLevels - 1);
struct TextureView {
  const uint32_t* texels;  // Texture::texels as words, R in the low byte
  int32_t width[kMaxTextureLevels], height[kMaxTextureLevels], offset[kMaxTextureLevels];  // per level
  int32_t lastLevel;
  float baseSide;           // max(width, height) of level 0
  const float* colour;      // per code: the linear value of an R, G or B code in its encoding
  const float* alpha;       // per code: code / 255
  TextureWrap wrapU, wrapV;
};
TextureView ViewOf(const Texture& texture);

// Trilinear sample with the texture's addressing (repeat unless set). `footprint` is the larger screen-pixel footprint
// of the lookup in UV units (max of |dUV/dx|, |dUV/dy|); it picks the mip level. Returns linear values.
glm::vec4 SampleTexture(const Texture& texture, glm::vec2 uv, float footprint);
// A normal map's sample: SampleTexture's r, g, b, and in a, instead of alpha, each texel's own
// normal length |rgb * 2 - 1| filtered alike. A coarse level's texel is the mean of the normals
// below it, shorter where they disagree (Toksvig's |N|); level 0's are unit but for their codes'
// rounding. Filtering the lengths, unlike the length of the filtered normal, does not take the
// bilinear blend of two texels under a magnified pixel for a spread of normals within it.
glm::vec4 SampleNormalTexture(const Texture& texture, glm::vec2 uv, float footprint);

}  // namespace ssgi
