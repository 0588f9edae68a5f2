#include "core/gbuffer.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include <catch2/catch.hpp>

#include "core/color.h"

namespace ssgi {
namespace {

double AngleDegrees(glm::vec3 a, glm::vec3 b) {
  const double c = std::clamp(double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z, -1.0, 1.0);
  return std::acos(c) * 180.0 / 3.14159265358979323846;
}

// Max angular error of an encoding over random unit normals plus the axes and octant diagonals.
double MaxNormalError(NormalEncoding encoding) {
  std::mt19937 rng(1234);
  std::normal_distribution<float> gauss;
  double worst = 0.0;
  auto probe = [&](glm::vec3 n) {
    n = glm::normalize(n);
    const glm::vec3 decoded = DecodeNormal(EncodeNormal(n, encoding), encoding);
    REQUIRE(std::abs(glm::length(decoded) - 1.0f) < 1e-5f);
    worst = std::max(worst, AngleDegrees(n, decoded));
  };
  for (int i = 0; i < 400000; ++i) probe({gauss(rng), gauss(rng), gauss(rng)});
  for (int sx = -1; sx <= 1; ++sx)
    for (int sy = -1; sy <= 1; ++sy)
      for (int sz = -1; sz <= 1; ++sz)
        if (sx || sy || sz) probe({float(sx), float(sy), float(sz)});
  return worst;
}

TEST_CASE("normal encodings: measured max angular error", "[gbuffer]") {
  const double xyz8 = MaxNormalError(NormalEncoding::kXyz8);
  const double oct24 = MaxNormalError(NormalEncoding::kOct24);
  WARN("max angular error: xyz8 " << xyz8 << " deg, oct24 " << oct24 << " deg");
  // docs/design.md §3: about 0.39 deg for the paper's 3 x 8 bits, about 0.06 deg for octahedral 2 x 12.
  CHECK(xyz8 > 0.2);
  CHECK(xyz8 < 0.45);
  CHECK(oct24 < 0.07);
  CHECK(oct24 * 4.0 < xyz8);
}

TEST_CASE("the packed words round-trip", "[gbuffer]") {
  for (int code = 0; code < 256; ++code) {
    const float linear = SrgbCodeToLinear(uint8_t(code));
    CHECK(LinearToSrgbCode(linear) == code);
    const uint32_t w0 = PackAlbedoMetallic(glm::vec3(linear, SrgbCodeToLinear(uint8_t(255 - code)), linear),
                                           float(code) / 255.0f);
    CHECK((w0 & 0xFFu) == uint32_t(code));
    CHECK(((w0 >> 8) & 0xFFu) == uint32_t(255 - code));
    CHECK(UnpackMetallic(w0) == float(code) / 255.0f);
    CHECK(UnpackAlbedo(w0).x == linear);
    const uint32_t w1 = PackNormalRoughness({0.0f, 0.0f, 1.0f}, float(code) / 255.0f, NormalEncoding::kOct24);
    CHECK(UnpackRoughness(w1) == float(code) / 255.0f);
  }
  CHECK(UnpackDepth(PackDepth(12.375f)) == 12.375f);
  CHECK(UnpackDepth(PackDepth(kBackgroundDepth)) == kBackgroundDepth);
  const uint32_t shadowed = PackShadowTerm(true, 0.75f);
  CHECK(UnpackHardShadow(shadowed));
  CHECK(UnpackBlockerDistance(shadowed) == 0.75f);
  CHECK_FALSE(UnpackHardShadow(PackShadowTerm(false, 2.5f)));
  CHECK(UnpackBlockerDistance(kShadowLit) == 0.0f);
  // Out-of-range and NaN inputs clamp instead of wrapping into neighbouring fields.
  CHECK(PackAlbedoMetallic(glm::vec3(7.0f, -1.0f, std::nanf("")), 2.0f) == 0xFF0000FFu);
}

TEST_CASE("8-bit sRGB encoding is round(LinearToSrgb(x) * 255) for every float in [0, 1]", "[color]") {
  // Every float bit pattern from 0 to 1 against the exact definition in double precision. The
  // exhaustive walk takes about a second; a stride keeps it fast while covering every bucket.
  size_t checked = 0, mismatches = 0;
  for (uint32_t bits = 0; bits <= 0x3F800000u; bits += 7) {
    float x;
    std::memcpy(&x, &bits, 4);
    const double encoded = x <= 0.0031308 ? x * 12.92 : 1.055 * std::pow(double(x), 1.0 / 2.4) - 0.055;
    const double scaled = encoded * 255.0;
    // Values within 1e-4 of a rounding boundary may round either way between float and double.
    if (std::abs(scaled - std::floor(scaled) - 0.5) < 1e-4) continue;
    mismatches += LinearToSrgbCode(x) != uint8_t(std::lround(scaled));
    ++checked;
  }
  CHECK(checked > 100000000u);
  CHECK(mismatches == 0);
  CHECK(LinearToSrgbCode(1.0f) == 255);
  CHECK(LinearToSrgbCode(1e9f) == 255);
  CHECK(LinearToSrgbCode(-1.0f) == 0);
  CHECK(LinearToSrgbCode(std::nanf("")) == 0);
  CHECK(LinearToSrgbCode(std::numeric_limits<float>::infinity()) == 255);
}

TEST_CASE("a fresh G-buffer is background everywhere, padding included", "[gbuffer]") {
  const GBuffer g = MakeGBuffer(5, 3, NormalEncoding::kOct24);
  for (int w = 0; w < 4; ++w) {
    const size_t perRow = g.word[w].bytes_per_row() / 4;
    for (size_t y = 0; y < 3; ++y)
      for (size_t x = 0; x < perRow; ++x)
        CHECK(g.word[w].ConstRow(y)[x] == (w == 2 ? PackDepth(kBackgroundDepth) : 0u));
  }
}

}  // namespace
}  // namespace ssgi
