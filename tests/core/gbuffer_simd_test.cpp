// The Highway twins of the G-buffer's unpacking (core/gbuffer-inl.h) against the scalar functions,
// bit for bit, on every compiled and supported target: every xyz8 and oct24 normal code (the
// roughness byte varied along), every roughness code; every albedo code (the metallic byte varied
// along), every metallic code; every top 24 bits of the shadow term.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tests/core/gbuffer_simd_test.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "core/color.h"
#include "core/gbuffer-inl.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Unpacks `count` words 1 (a multiple of the vector length) into normals and roughness.
void UnpackWords(const uint32_t* words, size_t count, bool oct24, float* x, float* y, float* z, float* roughness) {
  const hn::ScalableTag<float> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  for (size_t i = 0; i < count; i += hn::Lanes(d)) {
    const auto word = hn::LoadU(du, words + i);
    const auto n = UnpackNormalV(d, word, oct24 ? NormalEncoding::kOct24 : NormalEncoding::kXyz8);
    hn::StoreU(n.x, d, x + i);
    hn::StoreU(n.y, d, y + i);
    hn::StoreU(n.z, d, z + i);
    hn::StoreU(UnpackRoughnessV(d, word), d, roughness + i);
  }
}

// Unpacks `count` words 0 (a multiple of the vector length) into linear albedo and metallic.
void UnpackWords0(const uint32_t* words, size_t count, float* r, float* g, float* b, float* metallic) {
  const hn::ScalableTag<float> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  const float* srgbDecodeTable = SrgbDecodeTableForKernels();
  for (size_t i = 0; i < count; i += hn::Lanes(d)) {
    const auto word = hn::LoadU(du, words + i);
    const auto albedo = UnpackAlbedoV(d, word, srgbDecodeTable);
    hn::StoreU(albedo.x, d, r + i);
    hn::StoreU(albedo.y, d, g + i);
    hn::StoreU(albedo.z, d, b + i);
    hn::StoreU(UnpackMetallicV(d, word), d, metallic + i);
  }
}

// Unpacks `count` words 3 (a multiple of the vector length) into hard flags (1 or 0) and blocker
// distances.
void UnpackShadowTerms(const uint32_t* words, size_t count, uint32_t* hard, float* distance) {
  const hn::ScalableTag<float> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  for (size_t i = 0; i < count; i += hn::Lanes(d)) {
    const auto word = hn::LoadU(du, words + i);
    hn::StoreU(hn::VecFromMask(du, hn::RebindMask(du, UnpackHardShadowV(d, word))), du, hard + i);
    hn::StoreU(UnpackBlockerDistanceV(d, word), d, distance + i);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <cstring>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/test_support.h"

namespace ssgi {
HWY_EXPORT(UnpackWords);
HWY_EXPORT(UnpackWords0);
HWY_EXPORT(UnpackShadowTerms);

namespace {

bool SameBits(float a, float b) { return std::memcmp(&a, &b, sizeof(float)) == 0; }

// Every 24-bit code (a multiple of every vector length: 2^24), each with another top byte.
std::vector<uint32_t> EveryLowCode() {
  std::vector<uint32_t> words(size_t(1) << 24);
  for (uint32_t code = 0; code < words.size(); ++code) words[code] = code | (code * 2654435761u & 0xFF000000u);
  return words;
}

TEST_CASE("G-buffer unpacking: the SIMD twins equal the scalar functions on every target", "[gbuffer][simd]") {
  for (const NormalEncoding encoding : {NormalEncoding::kXyz8, NormalEncoding::kOct24}) {
    const std::vector<uint32_t> words = EveryLowCode();
    std::vector<float> expected(words.size() * 4);
    for (size_t i = 0; i < words.size(); ++i) {
      const glm::vec3 n = UnpackNormal(words[i], encoding);
      expected[4 * i] = n.x;
      expected[4 * i + 1] = n.y;
      expected[4 * i + 2] = n.z;
      expected[4 * i + 3] = UnpackRoughness(words[i]);
    }
    std::vector<float> x(words.size()), y(words.size()), z(words.size()), roughness(words.size());
    const size_t targets = test::ForEachSimdTarget([&](const char* target) {
      HWY_DYNAMIC_DISPATCH(UnpackWords)(words.data(), words.size(), encoding == NormalEncoding::kOct24, x.data(),
                                         y.data(), z.data(), roughness.data());
      size_t mismatches = 0, first = 0;
      for (size_t i = 0; i < words.size(); ++i) {
        const bool same = SameBits(x[i], expected[4 * i]) && SameBits(y[i], expected[4 * i + 1]) &&
                          SameBits(z[i], expected[4 * i + 2]) && SameBits(roughness[i], expected[4 * i + 3]);
        if (!same && mismatches++ == 0) first = i;
      }
      CAPTURE(target, int(encoding), first, words[first]);
      CHECK(mismatches == 0);
    });
    CHECK(targets >= 1);
  }
}

TEST_CASE("G-buffer albedo and metallic: the SIMD twins equal the scalar functions on every target",
          "[gbuffer][simd]") {
  const std::vector<uint32_t> words = EveryLowCode();
  std::vector<float> expected[4], actual[4];
  for (std::vector<float>& channel : expected) channel.resize(words.size());
  for (std::vector<float>& channel : actual) channel.resize(words.size());
  for (size_t i = 0; i < words.size(); ++i) {
    const glm::vec3 albedo = UnpackAlbedo(words[i]);
    for (int c = 0; c < 3; ++c) expected[c][i] = albedo[c];
    expected[3][i] = UnpackMetallic(words[i]);
  }
  const size_t targets = test::ForEachSimdTarget([&](const char* target) {
    HWY_DYNAMIC_DISPATCH(UnpackWords0)(words.data(), words.size(), actual[0].data(), actual[1].data(),
                                        actual[2].data(), actual[3].data());
    for (int c = 0; c < 4; ++c) {
      const size_t first = test::FirstDifferentBits(actual[c].data(), expected[c].data(), words.size());
      CAPTURE(target, c, first);
      CHECK(first == words.size());
    }
  });
  CHECK(targets >= 1);
}

TEST_CASE("G-buffer shadow term: the SIMD twins equal the scalar functions on every target", "[gbuffer][simd]") {
  // Every value of the top 24 bits (the flag, the exponent, the high mantissa bits: zero, denormal,
  // normal, infinite and NaN distances), the low byte varied along; 2^24 words, a multiple of every
  // vector length.
  std::vector<uint32_t> words(size_t(1) << 24);
  for (uint32_t i = 0; i < words.size(); ++i) words[i] = i << 8 | ((i * 2654435761u) >> 24);
  std::vector<uint32_t> hard(words.size());
  std::vector<float> distance(words.size());
  const size_t targets = test::ForEachSimdTarget([&](const char* target) {
    HWY_DYNAMIC_DISPATCH(UnpackShadowTerms)(words.data(), words.size(), hard.data(), distance.data());
    size_t mismatches = 0, first = 0;
    for (size_t i = 0; i < words.size(); ++i) {
      const bool same = (hard[i] != 0) == UnpackHardShadow(words[i]) &&
                        SameBits(distance[i], UnpackBlockerDistance(words[i]));
      if (!same && mismatches++ == 0) first = i;
    }
    CAPTURE(target, first, words[first]);
    CHECK(mismatches == 0);
  });
  CHECK(targets >= 1);
}

}  // namespace
}  // namespace ssgi
#endif
