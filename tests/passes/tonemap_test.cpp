#include "passes/tonemap.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "core/color.h"
#include "core/parallel.h"
#include "passes/frame/frame.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

// Inputs that reach every branch: special values, the curve's range and float patterns spread over
// [0, 4] by bits (so every sRGB bucket and threshold neighbourhood is visited).
std::vector<float> TonemapInputs() {
  std::vector<float> values = {0.0f, -0.0f, -1.0f, 1.0f, 0.5f, 1e-30f, 1e30f, 65504.0f, 70000.0f,
                               std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                               std::nanf(""), std::numeric_limits<float>::denorm_min()};
  for (uint32_t bits = 0; bits <= 0x40800000u; bits += 61) {
    float x;
    std::memcpy(&x, &bits, 4);
    values.push_back(x);
  }
  std::mt19937 rng(5);
  std::lognormal_distribution<float> hdr(0.0f, 2.0f);
  for (int i = 0; i < 100000; ++i) values.push_back(hdr(rng));
  return values;
}

TEST_CASE("tonemap: the SIMD kernel equals the scalar definition on every compiled target", "[tonemap][simd]") {
  // The inputs in red, and shifted by one and by two values in green and blue, so each channel
  // sees every value next to different neighbours.
  const std::vector<float> inputs = TonemapInputs();
  std::vector<float> shifted[2];
  for (int s = 0; s < 2; ++s) {
    shifted[s] = inputs;
    std::rotate(shifted[s].begin(), shifted[s].begin() + 1 + s, shifted[s].end());
  }
  const float* const channels[3] = {inputs.data(), shifted[0].data(), shifted[1].data()};
  size_t targets = 0;
  for (Tonemap curve : {Tonemap::kAces, Tonemap::kClamp}) {
    for (float scale : {1.0f, 0.25f, 3.0f}) {
      std::vector<uint8_t> expected(inputs.size() * 3), actual(inputs.size() * 3);
      TonemapRowScalar(channels, inputs.size(), scale, curve, expected.data());
      targets += test::ForEachSimdTarget([&](const char* target) {
        // Every count up to a few vectors exercises the scalar tail too.
        for (size_t count : {inputs.size(), size_t(1), size_t(7), size_t(33)}) {
          std::fill(actual.begin(), actual.end(), uint8_t(0xAB));
          TonemapRowSimd(channels, count, scale, curve, actual.data());
          CAPTURE(target, count, scale);
          REQUIRE(std::equal(actual.begin(), actual.begin() + 3 * count, expected.begin()));
          // Nothing past the row is written.
          REQUIRE(std::all_of(actual.begin() + 3 * count, actual.end(), [](uint8_t v) { return v == 0xAB; }));
        }
      });
    }
  }
  CHECK(targets >= 6);
}

TEST_CASE("tonemap: ACES codes count the thresholds the curve reaches, for every float up to the largest input",
          "[tonemap]") {
  // Walks every float from 0 to kTonemapMaxInput in order: AcesCurve must never decrease (so each
  // code boundary is unique), and the table's code must be the number of the encoder's thresholds
  // the curve reaches. (In float arithmetic the curve is not monotone: it crosses code boundaries
  // back and forth at 131 floats, which is why the definition evaluates it in double.)
  const int32_t maxBits = std::bit_cast<int32_t>(kTonemapMaxInput);
  const float* thresholds = SrgbEncodeThresholds();
  std::atomic<int64_t> decreases{0}, mismatches{0}, firstMismatch{std::numeric_limits<int64_t>::max()};
  constexpr int32_t kChunk = 1 << 22;
  ParallelFor("test.tonemap_aces_codes", size_t(maxBits / kChunk) + 1, [&](size_t chunk) {
    const int32_t begin = int32_t(chunk) * kChunk, end = std::min(begin + kChunk - 1, maxBits);
    double previous = AcesCurve(begin > 0 ? std::bit_cast<float>(begin - 1) : 0.0f);
    int code = int(std::upper_bound(thresholds, thresholds + 255, previous,
                                    [](double value, float threshold) { return value < double(threshold); }) -
                   thresholds);
    int64_t chunkDecreases = 0, chunkMismatches = 0;
    for (int32_t bits = begin;; ++bits) {
      const float x = std::bit_cast<float>(bits);
      const double curve = AcesCurve(x);
      chunkDecreases += curve < previous;
      previous = curve;
      while (code < 255 && curve >= double(thresholds[code])) ++code;
      if (int(TonemapCode(x, Tonemap::kAces)) != (x > 0.0f ? code : 0)) {
        ++chunkMismatches;
        int64_t first = firstMismatch.load();
        while (bits < first && !firstMismatch.compare_exchange_weak(first, bits)) {
        }
      }
      if (bits == end) break;
    }
    decreases += chunkDecreases;
    mismatches += chunkMismatches;
  });
  CAPTURE(firstMismatch.load());
  CHECK(decreases.load() == 0);
  CHECK(mismatches.load() == 0);
  // The clamp curve is the sRGB encoder of min(x, 1).
  size_t clampMismatches = 0;
  for (uint32_t bits = 0; bits <= uint32_t(maxBits); bits += 4099) {
    const float x = std::bit_cast<float>(bits);
    clampMismatches += TonemapCode(x, Tonemap::kClamp) != LinearToSrgbCode(std::min(x, 1.0f));
  }
  CHECK(clampMismatches == 0);
}

TEST_CASE("tonemap: special values encode as documented", "[tonemap]") {
  const float in[] = {std::nanf(""), -5.0f, 0.0f, std::numeric_limits<float>::infinity(), 1e6f};
  const float* const channels[3] = {in, in, in};
  uint8_t codes[15];
  TonemapRowScalar(channels, 5, 1.0f, Tonemap::kAces, codes);
  for (int c = 0; c < 3; ++c) {
    CHECK(codes[0 + c] == 0);
    CHECK(codes[3 + c] == 0);
    CHECK(codes[6 + c] == 0);
    CHECK(codes[9 + c] == 255);
    CHECK(codes[12 + c] == 255);
  }
  // Mid-grey through the clamp curve is its sRGB code, in each channel's own byte.
  const float grey = SrgbCodeToLinear(128), black = 0.0f, white = 1.0f;
  const float* const greyRed[3] = {&grey, &black, &white};
  TonemapRowScalar(greyRed, 1, 1.0f, Tonemap::kClamp, codes);
  CHECK(int(codes[0]) == 128);
  CHECK(int(codes[1]) == 0);
  CHECK(int(codes[2]) == 255);
}

TEST_CASE("tonemap: the SIMD pass gives the scalar pass's bytes on the default scene on every target, "
          "into a kept buffer", "[tonemap][simd]") {
  test::ForEachDefaultSceneFrame([](const Frame& frame) {
    TonemapOutputs scalar;
    RunTonemap(frame.Result(), {}, scalar, KernelPath::kScalar);
    const size_t targets = test::ForEachSimdTarget([&](const char* target) {
      // A buffer of the right size holding other bytes: the pass must overwrite every one.
      TonemapOutputs simd;
      simd.rgb.assign(scalar.rgb.size(), 0xA5);
      RunTonemap(frame.Result(), {}, simd, KernelPath::kSimd);
      CAPTURE(target, frame.view.width, frame.view.height);
      CHECK((simd.rgb == scalar.rgb));  // parenthesised: Catch would print every byte
    });
    CHECK(targets >= 1);
  });
}

}  // namespace
}  // namespace ssgi
