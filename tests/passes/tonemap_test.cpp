#include "passes/tonemap.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "core/color.h"
#include "passes/frame.h"
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
  const std::vector<float> inputs = TonemapInputs();
  size_t targets = 0;
  for (Tonemap curve : {Tonemap::kAces, Tonemap::kClamp}) {
    for (float scale : {1.0f, 0.25f, 3.0f}) {
      std::vector<uint8_t> expected(inputs.size()), actual(inputs.size());
      TonemapRowScalar(inputs.data(), inputs.size(), scale, curve, expected.data());
      targets += test::ForEachSimdTarget([&](const char* target) {
        // Every count up to a few vectors exercises the scalar tail too.
        for (size_t count : {inputs.size(), size_t(1), size_t(7), size_t(33)}) {
          std::fill(actual.begin(), actual.end(), uint8_t(0xAB));
          TonemapRowSimd(inputs.data(), count, scale, curve, actual.data());
          CAPTURE(target, count, scale);
          REQUIRE(std::equal(actual.begin(), actual.begin() + count, expected.begin()));
        }
      });
    }
  }
  CHECK(targets >= 6);
}

TEST_CASE("tonemap: special values encode as documented", "[tonemap]") {
  const float in[] = {std::nanf(""), -5.0f, 0.0f, std::numeric_limits<float>::infinity(), 1e6f};
  uint8_t codes[5];
  TonemapRowScalar(in, 5, 1.0f, Tonemap::kAces, codes);
  CHECK(codes[0] == 0);
  CHECK(codes[1] == 0);
  CHECK(codes[2] == 0);
  CHECK(codes[3] == 255);
  CHECK(codes[4] == 255);
  // Mid-grey through the clamp curve is its sRGB code.
  const float grey = SrgbCodeToLinear(128);
  TonemapRowScalar(&grey, 1, 1.0f, Tonemap::kClamp, codes);
  CHECK(int(codes[0]) == 128);
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
      CHECK(simd.rgb == scalar.rgb);
    });
    CHECK(targets >= 1);
  });
}

}  // namespace
}  // namespace ssgi
