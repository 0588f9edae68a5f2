#include "core/texture.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cmath>
#include <string>

#include "core/check.h"
#include "core/color.h"
#include "core/error.h"

namespace ssgi {
namespace {

float DecodeColor(uint8_t code, TextureEncoding encoding) {
  return encoding == TextureEncoding::kSrgb ? SrgbCodeToLinear(code) : float(code) / 255.0f;
}

// Linear RGBA floats of `count` 8-bit values (texels times 4); alpha is linear in every encoding.
std::vector<float> DecodeLevel(const uint8_t* rgba, size_t count, TextureEncoding encoding) {
  std::vector<float> linear(count);
  for (size_t i = 0; i < count; i += 4) {
    for (size_t c = 0; c < 3; ++c) linear[i + c] = DecodeColor(rgba[i + c], encoding);
    linear[i + 3] = float(rgba[i + 3]) / 255.0f;
  }
  return linear;
}

// Appends a level of these linear RGBA values, encoded, to the texture.
void AppendLevel(Texture& texture, int width, int height, const std::vector<float>& linear) {
  texture.levels.push_back({width, height, texture.texels.size() / 4});
  const size_t first = texture.texels.size();
  texture.texels.resize(first + linear.size());
  uint8_t* rgba = texture.texels.data() + first;
  for (size_t i = 0; i < linear.size(); i += 4) {
    for (size_t c = 0; c < 3; ++c)
      rgba[i + c] =
          texture.encoding == TextureEncoding::kSrgb ? LinearToSrgbCode(linear[i + c]) : UnormCode8(linear[i + c]);
    rgba[i + 3] = UnormCode8(linear[i + 3]);
  }
}

// log2 for x > 1 (normal, finite) from its exponent and mantissa bits and the atanh series of ln,
// not libm, so every build and SIMD target picks the same mip blend (docs/design.md §11). |s| < 1/3, so
// six terms are accurate to ~1e-7.
float Log2(float x) {
  const uint32_t bits = std::bit_cast<uint32_t>(x);
  const int exponent = int((bits >> 23) & 0xFFu) - 126;  // std::frexp's: x = m 2^exponent, m in [0.5, 1)
  const float mantissa = std::bit_cast<float>((bits & 0x7FFFFFu) | 0x3F800000u);  // 2 m, in [1, 2)
  const float s = (mantissa - 1.0f) / (mantissa + 1.0f);
  const float s2 = s * s;
  const float series =
      1.0f + s2 * (1.0f / 3.0f + s2 * (1.0f / 5.0f + s2 * (1.0f / 7.0f + s2 * (1.0f / 9.0f + s2 * (1.0f / 11.0f)))));
  constexpr float kInvLn2 = 1.44269504f;
  return float(exponent - 1) + 2.0f * s * series * kInvLn2;
}

// Fraction of a texture coordinate in [0, 1] (1 only by rounding); non-finite coordinates read as 0.
float Repeat(float x) { return std::isfinite(x) ? x - std::floor(x) : 0.0f; }

int WrapIndex(int i, int size) { return i < 0 ? i + size : (i >= size ? i - size : i); }
// The coordinate in [0, 1] under `wrap`, 0 for a non-finite one.
float WrapCoordinate(float x, TextureWrap wrap) {
  if (!std::isfinite(x)) return 0.0f;
  if (wrap == TextureWrap::kClamp) return std::min(std::max(x, 0.0f), 1.0f);
  if (wrap == TextureWrap::kMirror) {
    const float t = x - 2.0f * std::floor(x * 0.5f);  // in [0, 2]
    return t > 1.0f ? 2.0f - t : t;
  }
  return Repeat(x);
}
// A texel index one beyond an edge ([-1, size]): the other side's for kRepeat, the edge's otherwise.
int EdgeIndex(int i, int size, TextureWrap wrap) {
  if (wrap == TextureWrap::kRepeat) return WrapIndex(i, size);
  return i < 0 ? 0 : (i >= size ? size - 1 : i);
}

// DecodeColor and the alpha's code / 255 as tables, looked up once per sample rather than per
// channel: the same values, without a call per channel in the resolve's hottest loop.
struct TexelDecoding {
  const float* colour;  // per code: DecodeColor(code, encoding)
  const float* alpha;   // per code: code / 255
  // A normal map's: alpha replaced by the length of the texel's normal, rgb * 2 - 1.
  bool normalLengthInAlpha = false;
};

TexelDecoding DecodingOf(TextureEncoding encoding) {
  static const std::array<float, 256> unorm = [] {
    std::array<float, 256> table{};
    for (int code = 0; code < 256; ++code) table[size_t(code)] = float(code) / 255.0f;
    return table;
  }();
  return {encoding == TextureEncoding::kSrgb ? SrgbDecodeTableForKernels() : unorm.data(), unorm.data(), false};
}

glm::vec4 Texel(const uint8_t* levelTexels, const TextureLevel& level, int x, int y, const TexelDecoding& decoding) {
  const uint8_t* t = levelTexels + (size_t(y) * size_t(level.width) + size_t(x)) * 4;
  const glm::vec4 texel(decoding.colour[t[0]], decoding.colour[t[1]], decoding.colour[t[2]], decoding.alpha[t[3]]);
  if (!decoding.normalLengthInAlpha) return texel;
  return {glm::vec3(texel), glm::length(glm::vec3(texel) * 2.0f - 1.0f)};
}

// u, v in [0, 1]; texel centres at (i + 0.5) / size, v = 0 at the bottom row.
glm::vec4 SampleBilinear(const Texture& texture, const TextureLevel& level, float u, float v,
                         const TexelDecoding& encoding) {
  const uint8_t* texels = texture.Texels(level);
  const float x = u * float(level.width) - 0.5f;
  const float y = (1.0f - v) * float(level.height) - 0.5f;
  const float x0 = std::floor(x);
  const float y0 = std::floor(y);
  const float fx = x - x0;
  const float fy = y - y0;
  const int ix0 = EdgeIndex(int(x0), level.width, texture.wrapU);
  const int ix1 = EdgeIndex(int(x0) + 1, level.width, texture.wrapU);
  const int iy0 = EdgeIndex(int(y0), level.height, texture.wrapV);
  const int iy1 = EdgeIndex(int(y0) + 1, level.height, texture.wrapV);
  const glm::vec4 top =
      Texel(texels, level, ix0, iy0, encoding) * (1.0f - fx) + Texel(texels, level, ix1, iy0, encoding) * fx;
  const glm::vec4 bottom =
      Texel(texels, level, ix0, iy1, encoding) * (1.0f - fx) + Texel(texels, level, ix1, iy1, encoding) * fx;
  return top * (1.0f - fy) + bottom * fy;
}

}  // namespace

Texture LoadTexture(const std::filesystem::path& file, TextureEncoding encoding) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) throw InputError(file, "image file not found");
  // Colour under alpha as stored: OIIO would premultiply, darkening the mips of cut-out edges.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  OIIO::ImageBuf image(file.string(), 0, 0, nullptr, &config);
  // Checked from the header, before the pixels are read.
  if (image.spec().width > kMaxTextureSide || image.spec().height > kMaxTextureSide)
    throw InputError(file, "image is " + std::to_string(image.spec().width) + "x" + std::to_string(image.spec().height) +
                               "; textures may be at most " + std::to_string(kMaxTextureSide) + " texels a side");
  if (!image.read(0, 0, true, OIIO::TypeDesc::UINT8)) throw InputError(file, "cannot read image: " + image.geterror());
  const int channels = image.nchannels();
  if (channels < 1 || channels > 4)
    throw InputError(file, "image has " + std::to_string(channels) + " channels; textures need 1 to 4");

  // Grey replicates to RGB; a missing alpha channel reads as opaque.
  static constexpr int kOrder[4][4] = {{0, 0, 0, -1}, {0, 0, 0, 1}, {0, 1, 2, -1}, {0, 1, 2, 3}};
  static constexpr float kFill[4] = {0.0f, 0.0f, 0.0f, 1.0f};
  const OIIO::ImageBuf rgbaImage = OIIO::ImageBufAlgo::channels(image, 4, kOrder[channels - 1], kFill);
  if (rgbaImage.has_error()) throw InputError(file, "cannot read image: " + rgbaImage.geterror());

  const OIIO::ROI roi = rgbaImage.roi();
  std::vector<uint8_t> rgba(size_t(roi.width()) * size_t(roi.height()) * 4);
  if (!rgbaImage.get_pixels(roi, OIIO::TypeDesc::UINT8, rgba.data()))
    throw InputError(file, "cannot read image: " + rgbaImage.geterror());
  Texture texture = MakeTexture(roi.width(), roi.height(), std::move(rgba), encoding);
  texture.sourceChannels = channels;
  return texture;
}

Texture MakeTexture(int width, int height, std::vector<uint8_t> rgba, TextureEncoding encoding) {
  SSGI_CHECK_GT(width, 0);
  SSGI_CHECK_GT(height, 0);
  SSGI_CHECK_LE(width, kMaxTextureSide);
  SSGI_CHECK_LE(height, kMaxTextureSide);
  SSGI_CHECK_EQ(rgba.size(), size_t(width) * size_t(height) * 4);
  Texture texture;
  texture.encoding = encoding;
  texture.levels.push_back({width, height, 0});
  texture.texels = std::move(rgba);

  // Each level is a box-filtered reduction of the previous one's linear values (not of its 8-bit
  // codes, so rounding does not accumulate down the chain). OIIO's box of one destination texel
  // covers the 2x2 source texels, or 2-3 per axis for odd sizes (5 -> 2 averages texels 0-2 and 2-4).
  std::vector<float> linear = DecodeLevel(texture.texels.data(), texture.texels.size(), encoding);
  while (width > 1 || height > 1) {
    const int nextWidth = std::max(1, width / 2);
    const int nextHeight = std::max(1, height / 2);
    std::vector<float> next(size_t(nextWidth) * size_t(nextHeight) * 4);
    const OIIO::ImageBuf source(OIIO::ImageSpec(width, height, 4, OIIO::TypeDesc::FLOAT), linear.data());
    OIIO::ImageBuf target(OIIO::ImageSpec(nextWidth, nextHeight, 4, OIIO::TypeDesc::FLOAT), next.data());
    const bool resized = OIIO::ImageBufAlgo::resize(target, source, "box", 1.0f);
    SSGI_CHECK(resized);
    AppendLevel(texture, nextWidth, nextHeight, next);
    linear = std::move(next);
    width = nextWidth;
    height = nextHeight;
  }
  return texture;
}

TextureView ViewOf(const Texture& texture) {
  SSGI_CHECK_LE(texture.levels.size(), size_t(kMaxTextureLevels));
  SSGI_CHECK_LE(texture.texels.size() / 4, size_t(INT32_MAX));
  TextureView view{};
  view.texels = reinterpret_cast<const uint32_t*>(texture.texels.data());
  for (size_t k = 0; k < texture.levels.size(); ++k) {
    view.width[k] = texture.levels[k].width;
    view.height[k] = texture.levels[k].height;
    view.offset[k] = int32_t(texture.levels[k].offset);
  }
  view.lastLevel = int32_t(texture.levels.size()) - 1;
  view.baseSide = float(std::max(texture.levels[0].width, texture.levels[0].height));
  const TexelDecoding decoding = DecodingOf(texture.encoding);
  view.colour = decoding.colour;
  view.alpha = decoding.alpha;
  view.wrapU = texture.wrapU;
  view.wrapV = texture.wrapV;
  return view;
}

namespace {

glm::vec4 SampleTrilinear(const Texture& texture, glm::vec2 uv, float footprint, const TexelDecoding& decoding) {
  const TextureLevel& base = texture.levels.front();
  const int lastLevel = int(texture.levels.size()) - 1;
  const float scaled = footprint * float(std::max(base.width, base.height));
  float lambda = 0.0f;  // also for a zero or NaN footprint
  if (scaled >= float(1 << lastLevel)) {
    lambda = float(lastLevel);
  } else if (scaled > 1.0f) {
    lambda = Log2(scaled);
  }
  const float u = WrapCoordinate(uv.x, texture.wrapU);
  const float v = WrapCoordinate(uv.y, texture.wrapV);
  const int level = int(lambda);
  const float blend = lambda - float(level);
  const glm::vec4 fine = SampleBilinear(texture, texture.levels[level], u, v, decoding);
  if (blend == 0.0f) return fine;
  const glm::vec4 coarse = SampleBilinear(texture, texture.levels[level + 1], u, v, decoding);
  return fine * (1.0f - blend) + coarse * blend;
}

}  // namespace

glm::vec4 SampleTexture(const Texture& texture, glm::vec2 uv, float footprint) {
  return SampleTrilinear(texture, uv, footprint, DecodingOf(texture.encoding));
}

glm::vec4 SampleNormalTexture(const Texture& texture, glm::vec2 uv, float footprint) {
  TexelDecoding decoding = DecodingOf(texture.encoding);
  decoding.normalLengthInAlpha = true;
  return SampleTrilinear(texture, uv, footprint, decoding);
}

}  // namespace ssgi
