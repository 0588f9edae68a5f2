#include "core/texture.h"

#include <OpenImageIO/imageio.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "core/color.h"
#include "core/error.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

void WriteImage(const std::filesystem::path& file, int width, int height, int channels,
                const std::vector<uint8_t>& pixels) {
  auto out = OIIO::ImageOutput::create(file.string());
  REQUIRE(out);
  OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:UnassociatedAlpha", 1);  // write the colour values as given
  REQUIRE(out->open(file.string(), spec));
  REQUIRE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
  REQUIRE(out->close());
}

// Linear RGBA texture whose texel (x, y) (top row first) has red = 10 * (y * width + x) + 5.
Texture RampTexture(int width, int height) {
  std::vector<uint8_t> rgba;
  for (int i = 0; i < width * height; ++i) rgba.insert(rgba.end(), {uint8_t(10 * i + 5), 0, 0, 255});
  return MakeTexture(width, height, std::move(rgba), TextureEncoding::kLinear);
}

TEST_CASE("mip chains halve with floor down to 1x1, odd sizes included", "[texture]") {
  const Texture odd = RampTexture(5, 3);
  REQUIRE(odd.levels.size() == 3);
  CHECK((odd.levels[0].width == 5 && odd.levels[0].height == 3));
  CHECK((odd.levels[1].width == 2 && odd.levels[1].height == 1));
  CHECK((odd.levels[2].width == 1 && odd.levels[2].height == 1));
  size_t texels = 0;
  for (const TextureLevel& level : odd.levels) {
    CHECK(level.offset == texels);
    texels += size_t(level.width * level.height);
  }
  CHECK(odd.texels.size() == 4 * texels);

  const Texture strip = RampTexture(8, 1);
  REQUIRE(strip.levels.size() == 4);
  CHECK(strip.levels[3].width == 1);
  CHECK(RampTexture(1, 1).levels.size() == 1);
}

TEST_CASE("mip levels average linear values, not sRGB codes", "[texture]") {
  // Black and white: the linear mean 0.5 encodes to sRGB code 188; averaging codes would give 128.
  const Texture t = MakeTexture(2, 1, {0, 0, 0, 0, 255, 255, 255, 255}, TextureEncoding::kSrgb);
  REQUIRE(t.levels.size() == 2);
  CHECK(int(t.Texels(t.levels[1])[0]) == int(LinearToSrgbCode(0.5f)));
  CHECK(int(t.Texels(t.levels[1])[0]) == 188);
  CHECK(int(t.Texels(t.levels[1])[3]) == 128);  // alpha is linear in every encoding
}

TEST_CASE("sRGB texels decode to linear with the exact curve", "[texture]") {
  const Texture t = MakeTexture(1, 1, {128, 0, 255, 128}, TextureEncoding::kSrgb);
  const glm::vec4 s = SampleTexture(t, {0.5f, 0.5f}, 0.0f);
  CHECK(s.x == Approx(std::pow((128.0 / 255.0 + 0.055) / 1.055, 2.4)).epsilon(1e-6));
  CHECK(s.y == 0.0f);
  CHECK(s.z == 1.0f);
  CHECK(s.w == Approx(128.0f / 255.0f));
}

TEST_CASE("level 0 returns texel values at texel centres, v = 0 at the bottom row", "[texture]") {
  for (const auto& [width, height] : {std::pair{4, 2}, std::pair{5, 3}}) {
    const Texture t = RampTexture(width, height);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const glm::vec2 uv((float(x) + 0.5f) / float(width), 1.0f - (float(y) + 0.5f) / float(height));
        const float expected = float(10 * (y * width + x) + 5) / 255.0f;
        CHECK(SampleTexture(t, uv, 0.0f).x == Approx(expected).margin(1e-6));
      }
    }
  }
  // Power-of-two sizes put texel centres on exact binary fractions: exactly the texel.
  const Texture t = RampTexture(4, 2);
  CHECK(SampleTexture(t, {0.375f, 0.25f}, 0.0f).x == float(10 * 5 + 5) / 255.0f);  // texel (1, 1)
}

TEST_CASE("addressing repeats for negative, large and non-finite UVs", "[texture]") {
  const Texture t = RampTexture(4, 4);
  const glm::vec2 uv(0.3f, 0.7f);
  const glm::vec4 reference = SampleTexture(t, uv, 0.0f);
  CHECK(SampleTexture(t, uv + glm::vec2(3.0f, -2.0f), 0.0f).x == Approx(reference.x).margin(1e-5));
  CHECK(SampleTexture(t, {0.125f - 5.0f, 0.625f}, 0.0f).x == SampleTexture(t, {0.125f, 0.625f}, 0.0f).x);
  CHECK(SampleTexture(t, {1.0e6f + 0.125f, 0.625f}, 0.0f).x == SampleTexture(t, {0.125f, 0.625f}, 0.0f).x);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (const glm::vec2 bad : {glm::vec2(nan, nan), glm::vec2(inf, -inf), glm::vec2(1e30f, -1e30f)}) {
    const glm::vec4 s = SampleTexture(t, bad, 0.0f);
    CHECK((std::isfinite(s.x) && std::isfinite(s.w)));
  }
  CHECK(SampleTexture(t, {nan, nan}, 0.0f).x == SampleTexture(t, {0.0f, 0.0f}, 0.0f).x);
  // Wrapping blends the last column with the first: u = 0 is half texel 3, half texel 0 (top row 3).
  const float row3 = float(10 * 12 + 5) / 255.0f, row3Last = float(10 * 15 + 5) / 255.0f;
  CHECK(SampleTexture(t, {0.0f, 0.125f}, 0.0f).x == Approx(0.5f * (row3 + row3Last)));
}

TEST_CASE("the footprint selects and blends mip levels", "[texture]") {
  // Checker of 0 and 255: level 1 (1x1) is the mean, code 128.
  const Texture t =
      MakeTexture(2, 2, {0, 0, 0, 255, 255, 255, 255, 255, 255, 255, 255, 255, 0, 0, 0, 255}, TextureEncoding::kLinear);
  const glm::vec2 centre(0.25f, 0.75f);  // texel (0, 0) = 0
  CHECK(SampleTexture(t, centre, 0.0f).x == 0.0f);
  CHECK(SampleTexture(t, centre, 0.5f).x == 0.0f);  // one texel per pixel: level 0
  CHECK(SampleTexture(t, centre, std::numeric_limits<float>::quiet_NaN()).x == 0.0f);
  CHECK(SampleTexture(t, centre, 1.0f).x == 128.0f / 255.0f);  // lambda = log2(2) = 1
  CHECK(SampleTexture(t, centre, std::numeric_limits<float>::infinity()).x == 128.0f / 255.0f);
  // lambda = log2(1.5) = 0.585: that fraction of the way to level 1.
  CHECK(SampleTexture(t, centre, 0.75f).x == Approx(std::log2(1.5f) * 128.0f / 255.0f).epsilon(1e-5));
}

TEST_CASE("LoadTexture expands grey and RGB to RGBA", "[texture]") {
  test::ScratchDir dir("texture-load");
  WriteImage(dir / "grey.png", 2, 1, 1, {10, 200});
  const Texture grey = LoadTexture(dir / "grey.png", TextureEncoding::kLinear);
  CHECK(grey.sourceChannels == 1);
  REQUIRE(std::vector<uint8_t>(grey.texels.begin(), grey.texels.begin() + 8) ==
          std::vector<uint8_t>{10, 10, 10, 255, 200, 200, 200, 255});

  WriteImage(dir / "rgb.png", 1, 2, 3, {1, 2, 3, 4, 5, 6});
  const Texture rgb = LoadTexture(dir / "rgb.png", TextureEncoding::kSrgb);
  CHECK(rgb.sourceChannels == 3);
  CHECK(rgb.encoding == TextureEncoding::kSrgb);
  CHECK(std::vector<uint8_t>(rgb.texels.begin(), rgb.texels.begin() + 8) == std::vector<uint8_t>{1, 2, 3, 255, 4, 5, 6, 255});
  REQUIRE(rgb.levels.size() == 2);

  // Colour under alpha stays as stored (not premultiplied), so mips of cut-outs keep their colour.
  WriteImage(dir / "greyalpha.png", 1, 1, 2, {7, 99});
  const Texture greyAlpha = LoadTexture(dir / "greyalpha.png", TextureEncoding::kLinear);
  CHECK(greyAlpha.sourceChannels == 2);
  CHECK(std::vector<uint8_t>(greyAlpha.texels.begin(), greyAlpha.texels.begin() + 4) == std::vector<uint8_t>{7, 7, 7, 99});
}

TEST_CASE("LoadTexture reports missing and unreadable files by name", "[texture]") {
  test::ScratchDir dir("texture-errors");
  REQUIRE_THROWS_AS(LoadTexture(dir / "missing.png", TextureEncoding::kSrgb), InputError);
  REQUIRE_THROWS_WITH(LoadTexture(dir / "missing.png", TextureEncoding::kSrgb), Catch::Contains("missing.png"));
  test::WriteText(dir / "broken.png", "not a png");
  REQUIRE_THROWS_AS(LoadTexture(dir / "broken.png", TextureEncoding::kSrgb), InputError);
  REQUIRE_THROWS_WITH(LoadTexture(dir / "broken.png", TextureEncoding::kSrgb), Catch::Contains("broken.png"));
  // One texel past the longest side a mip chain of kMaxTextureLevels levels holds; the longest loads.
  WriteImage(dir / "wide.png", kMaxTextureSide + 1, 1, 1, std::vector<uint8_t>(size_t(kMaxTextureSide) + 1, 7));
  REQUIRE_THROWS_WITH(LoadTexture(dir / "wide.png", TextureEncoding::kLinear),
                      Catch::Contains("wide.png") && Catch::Contains("image is 32769x1; textures may be at most 32768"));
  WriteImage(dir / "longest.png", 1, kMaxTextureSide, 1, std::vector<uint8_t>(size_t(kMaxTextureSide), 7));
  CHECK(LoadTexture(dir / "longest.png", TextureEncoding::kLinear).levels.size() == size_t(kMaxTextureLevels));
}

TEST_CASE("texture: clamp and mirrored addressing read the edge texel beyond an edge and reflect every other repeat",
          "[texture]") {
  // Four texels in a row, codes 0, 85, 170, 255 (linear, one level 0 read: footprint 0).
  Texture texture = MakeTexture(4, 1, {0, 0, 0, 255, 85, 85, 85, 255, 170, 170, 170, 255, 255, 255, 255, 255},
                                TextureEncoding::kLinear);
  const auto at = [&](float u) { return SampleTexture(texture, {u, 0.5f}, 0.0f).x; };
  // Repeat: u = 1.125 is u = 0.125, texel 0's centre; u = 0 blends the first and last texels.
  CHECK(at(1.125f) == Approx(0.0f));
  CHECK(at(0.0f) == Approx(0.5f));
  texture.wrapU = TextureWrap::kClamp;
  CHECK(at(0.0f) == Approx(0.0f));  // the edge texel alone
  CHECK(at(-5.0f) == Approx(0.0f));
  CHECK(at(7.0f) == Approx(1.0f));
  CHECK(at(0.375f) == Approx(1.0f / 3.0f));  // inside, as repeat
  texture.wrapU = TextureWrap::kMirror;
  CHECK(at(1.125f) == Approx(1.0f));   // the second repeat is reflected: u = 0.875, texel 3
  CHECK(at(2.125f) == Approx(0.0f));   // the third is not
  CHECK(at(-0.125f) == Approx(0.0f));  // nor the one before, reflected: u = 0.125
  CHECK(at(1.0f) == Approx(1.0f));
}

}  // namespace
}  // namespace ssgi
