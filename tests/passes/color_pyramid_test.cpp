#include "passes/color_pyramid.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "core/parallel.h"
#include "core/pyramid.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

Plane3<float> ConstantImage(size_t width, size_t height, float value) {
  return MakePlane3<float>(width, height, value);
}

// A smooth random image: a positive sum of a few low-frequency waves with random phases per channel.
Plane3<float> SmoothRandomImage(size_t width, size_t height, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> phase(0.0f, 6.2831853f);
  Plane3<float> image = MakePlane3<float>(width, height, 0.0f);
  for (Plane<float>& channel : image.c) {
    const float px = phase(rng), py = phase(rng), pxy = phase(rng);
    for (size_t y = 0; y < height; ++y) {
      for (size_t x = 0; x < width; ++x) {
        channel.MutableRow(y)[x] = 1.0f + 0.4f * std::sin(0.07f * float(x) + px) +
                                   0.3f * std::sin(0.09f * float(y) + py) +
                                   0.2f * std::sin(0.05f * float(x + y) + pxy);
      }
    }
  }
  return image;
}

double Mean(const Plane<float>& plane) {
  double sum = 0.0;
  for (size_t y = 0; y < plane.ysize(); ++y) {
    for (size_t x = 0; x < plane.xsize(); ++x) sum += plane.ConstRow(y)[x];
  }
  return sum / double(plane.xsize() * plane.ysize());
}

TEST_CASE("Colour pyramid weights are Uludag's, normalised", "[color_pyramid]") {
  float sum = 0.0f;
  for (float w : kColorPyramidWeights) sum += w;
  CHECK(sum == Approx(1.0f).epsilon(1e-6));
  CHECK(kColorPyramidWeights[3] == Approx(0.474f / 0.998f));
  CHECK(kColorPyramidWeights[0] == kColorPyramidWeights[6]);
}

TEST_CASE("Colour pyramid level sizes follow the Hi-Z's for odd sizes", "[color_pyramid]") {
  ColorPyramid pyramid;
  const ColorPyramidStats stats = RunColorPyramid(ConstantImage(67, 45, 1.0f), pyramid);
  const std::vector<std::pair<size_t, size_t>> expected{{67, 45}, {33, 22}, {16, 11}, {8, 5},
                                                        {4, 2},   {2, 1},   {1, 1}};
  REQUIRE(pyramid.levels.size() == expected.size());
  size_t texels = 0;
  for (size_t k = 0; k < expected.size(); ++k) {
    for (const Plane<float>& channel : pyramid.levels[k].c) {
      CHECK(channel.xsize() == expected[k].first);
      CHECK(channel.ysize() == expected[k].second);
    }
    texels += expected[k].first * expected[k].second;
  }
  CHECK(stats.texels == texels);
  RunColorPyramid(ConstantImage(1, 5, 1.0f), pyramid);
  REQUIRE(pyramid.levels.size() == 3);
  CHECK(pyramid.levels[1].c[2].ysize() == 2);
}

TEST_CASE("Colour pyramid keeps a constant image constant at every level", "[color_pyramid]") {
  for (const float value : {1.0f, 0.37f, 1000.0f}) {
    ColorPyramid pyramid;
    RunColorPyramid(ConstantImage(67, 45, value), pyramid);
    for (const Plane3<float>& level : pyramid.levels) {
      for (const Plane<float>& channel : level.c) {
        for (size_t y = 0; y < channel.ysize(); ++y) {
          for (size_t x = 0; x < channel.xsize(); ++x)
            REQUIRE(channel.ConstRow(y)[x] == Approx(value).epsilon(1e-5));
        }
      }
    }
  }
}

TEST_CASE("Colour pyramid sanitises NaN, +inf and negative pixels so no level is poisoned",
          "[color_pyramid]") {
  struct Case {
    float bad;
    float sanitised;
  };
  const float inf = std::numeric_limits<float>::infinity();
  for (const Case c : {Case{std::numeric_limits<float>::quiet_NaN(), 0.0f}, Case{inf, kMaxRadiance},
                       Case{-inf, 0.0f}, Case{-3.0f, 0.0f}, Case{1e38f, kMaxRadiance}}) {
    for (const size_t x : {size_t(0), size_t(33), size_t(66)}) {
      Plane3<float> image = ConstantImage(67, 45, 0.5f);
      image.c[1].MutableRow(44)[x] = c.bad;
      ColorPyramid pyramid;
      RunColorPyramid(image, pyramid);
      CHECK(pyramid.levels[0].c[1].ConstRow(44)[x] == c.sanitised);
      for (const Plane3<float>& level : pyramid.levels) {
        for (const Plane<float>& channel : level.c) {
          for (size_t y = 0; y < channel.ysize(); ++y) {
            for (size_t i = 0; i < channel.xsize(); ++i) {
              const float v = channel.ConstRow(y)[i];
              REQUIRE(std::isfinite(v));
              REQUIRE(v >= 0.0f);
            }
          }
        }
      }
    }
  }
}

TEST_CASE("Colour pyramid built on a handed-over level 0 equals the pyramid built from a copy",
          "[color_pyramid][memory]") {
  for (const auto& [width, height] : {std::pair<size_t, size_t>{67, 45}, {1, 1}, {1, 5}, {300, 200}}) {
    CAPTURE(width, height);
    const Plane3<float> image = SmoothRandomImage(width, height, 7);
    for (KernelPath kernels : {KernelPath::kScalar, KernelPath::kSimd}) {
      ColorPyramid copied, handedOver;
      const ColorPyramidStats copiedStats = RunColorPyramid(image, copied, kernels);
      handedOver.levels.resize(1);
      handedOver.levels[0] = test::CopyOf(image);
      CHECK(RunColorPyramidOnLevelZero(handedOver, kernels).texels == copiedStats.texels);
      REQUIRE(handedOver.levels.size() == copied.levels.size());
      for (size_t k = 0; k < copied.levels.size(); ++k)
        for (size_t c = 0; c < 3; ++c) CHECK(test::SameBytes(handedOver.levels[k].c[c], copied.levels[k].c[c]));
    }
  }
}

// Random needs: per level some rows (a few whole, most a random column span), the rest none.
ColorPyramidNeeds RandomNeeds(const ColorPyramid& shape, std::mt19937& rng, int percentOfRows) {
  ColorPyramidNeeds needs;
  needs.rows.resize(shape.levels.size());
  for (size_t k = 1; k < shape.levels.size(); ++k) {
    const int width = int(shape.levels[k].c[0].xsize());
    needs.rows[k].resize(shape.levels[k].c[0].ysize());
    for (ColumnSpan& span : needs.rows[k]) {
      if (int(rng() % 100) >= percentOfRows) continue;
      const int a = int(rng() % uint32_t(width)), b = int(rng() % uint32_t(width));
      if (rng() % 8 == 0) span = {0, width};
      else span.Add(std::min(a, b), std::max(a, b));
    }
  }
  return needs;
}

TEST_CASE("Colour pyramid made only where needed equals the whole pyramid there", "[color_pyramid][plan]") {
  std::mt19937 rng(11);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const auto& [width, height] :
       {std::pair<size_t, size_t>{67, 45}, {1, 1}, {1, 5}, {300, 200}, {1023, 769}, {2048, 64}}) {
    const Plane3<float> image = SmoothRandomImage(width, height, 5);
    for (KernelPath kernels : {KernelPath::kScalar, KernelPath::kSimd}) {
      ColorPyramid whole;
      RunColorPyramid(image, whole, kernels);
      for (const int percent : {0, 3, 30, 100}) {
        CAPTURE(width, height, int(kernels), percent);
        const ColorPyramidNeeds needs = RandomNeeds(whole, rng, percent);
        // Levels filled with NaN: a needed texel made from a texel that was not made is NaN.
        ColorPyramid partial;
        for (const Plane3<float>& level : whole.levels)
          partial.levels.push_back(MakePlane3<float>(level.c[0].xsize(), level.c[0].ysize(), nan));
        partial.levels[0] = test::CopyOf(image);
        const ColorPyramidStats stats = RunColorPyramidOnLevelZero(partial, kernels, &needs);
        size_t needed = 0, differing = 0;
        for (size_t k = 1; k < whole.levels.size(); ++k) {
          for (size_t y = 0; y < needs.rows[k].size(); ++y) {
            const ColumnSpan span = needs.rows[k][y];
            for (int x = span.begin; x < span.end; ++x) {
              for (size_t c = 0; c < 3; ++c) {
                ++needed;
                differing += std::memcmp(&partial.levels[k].c[c].ConstRow(y)[x], &whole.levels[k].c[c].ConstRow(y)[x],
                                         sizeof(float)) != 0;
              }
            }
          }
        }
        CHECK(differing == 0);
        if (percent == 0) CHECK(stats.texels == width * height);  // level 0 only
        if (percent == 100 && width * height > 1) CHECK(needed > 0);
      }
    }
  }
}

// The number of level-0 texels along one axis that texel x of level k covers (sizes: level sizes).
size_t CoveredCount(size_t x, size_t k, const std::vector<size_t>& sizes) {
  size_t first = x, last = x;
  for (size_t level = k; level > 0; --level) {
    first = 2 * first;
    last = PyramidFootprintEnd(last, sizes[level], sizes[level - 1]);
  }
  return last - first + 1;
}

// Mean of a level with each texel weighted by the level-0 area it covers: at odd sizes the last
// column / row covers 3 source texels, not 2, so the plain mean over-weights the other texels.
double CoverageWeightedMean(const Plane<float>& plane, size_t k, const std::vector<size_t>& widths,
                            const std::vector<size_t>& heights) {
  double sum = 0.0, area = 0.0;
  for (size_t y = 0; y < plane.ysize(); ++y) {
    for (size_t x = 0; x < plane.xsize(); ++x) {
      const double weight = double(CoveredCount(x, k, widths) * CoveredCount(y, k, heights));
      sum += weight * plane.ConstRow(y)[x];
      area += weight;
    }
  }
  return sum / area;
}

TEST_CASE("Colour pyramid roughly preserves the mean of a smooth image", "[color_pyramid]") {
  SECTION("even sizes down to 2x1: plain mean") {
    ColorPyramid pyramid;
    RunColorPyramid(SmoothRandomImage(128, 64, 11), pyramid);
    for (size_t c = 0; c < 3; ++c) {
      const double mean0 = Mean(pyramid.levels[0].c[c]);
      for (size_t k = 1; k < pyramid.levels.size(); ++k) {
        INFO("channel " << c << " level " << k);
        CHECK(Mean(pyramid.levels[k].c[c]) == Approx(mean0).epsilon(0.01));
      }
    }
  }
  SECTION("odd sizes: mean weighted by covered area") {
    ColorPyramid pyramid;
    RunColorPyramid(SmoothRandomImage(67, 45, 11), pyramid);
    std::vector<size_t> widths, heights;
    for (const PyramidSize& size : PyramidLevelSizes(67, 45)) {
      widths.push_back(size.width);
      heights.push_back(size.height);
    }
    for (size_t c = 0; c < 3; ++c) {
      const double mean0 = Mean(pyramid.levels[0].c[c]);
      for (size_t k = 1; k < pyramid.levels.size(); ++k) {
        INFO("channel " << c << " level " << k);
        // Levels one texel tall: the 7-tap blur of a 2- or 4-texel level treats texels of unequal area
        // (67 -> ... -> 4 columns covering 16, 16, 16, 19) as equal; measured drift 3.7 %.
        const double tolerance = heights[k] == 1 ? 0.05 : 0.01;
        CHECK(CoverageWeightedMean(pyramid.levels[k].c[c], k, widths, heights) ==
              Approx(mean0).epsilon(tolerance));
      }
    }
  }
}

TEST_CASE("Colour pyramid is identical at 1, 2 and 3 threads", "[color_pyramid]") {
  Plane3<float> image = SmoothRandomImage(131, 77, 5);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> noise(0.0f, 4.0f);
  for (Plane<float>& channel : image.c) {
    for (size_t y = 0; y < channel.ysize(); ++y) {
      for (size_t x = 0; x < channel.xsize(); ++x) channel.MutableRow(y)[x] *= noise(rng);
    }
  }
  std::vector<ColorPyramid> results(3);
  for (int threads = 1; threads <= 3; ++threads) {
    const ThreadLimit limit(threads);
    RunColorPyramid(image, results[threads - 1]);
  }
  for (int i = 1; i < 3; ++i) {
    REQUIRE(results[i].levels.size() == results[0].levels.size());
    for (size_t k = 0; k < results[0].levels.size(); ++k) {
      for (size_t c = 0; c < 3; ++c) REQUIRE(test::SameBytes(results[i].levels[k].c[c], results[0].levels[k].c[c]));
    }
  }
}

// Floats of every magnitude and sign, denormals and values near the largest among them, and the
// special values: one in eight.
std::vector<float> AnyFloats(size_t count, std::mt19937& rng) {
  const std::vector<float> specials = test::SpecialFloats();
  std::uniform_int_distribution<size_t> pick(0, 8 * specials.size() - 1);
  std::uniform_real_distribution<float> mantissa(-1.0f, 1.0f);
  std::uniform_int_distribution<int> exponent(-140, 128);
  std::vector<float> values(count);
  for (float& v : values) {
    const size_t i = pick(rng);
    v = i < specials.size() ? specials[i] : std::ldexp(mantissa(rng), exponent(rng));
  }
  return values;
}

TEST_CASE("Colour pyramid: the SIMD row kernels equal the scalar definitions on every compiled target",
          "[color_pyramid][simd]") {
  constexpr size_t kWidth = 70;  // a few vectors of every target, and a tail
  std::mt19937 rng(17);
  // Level 0 takes any radiance: random bits (every kind of NaN among them) and the special values.
  std::vector<float> radiance = AnyFloats(kWidth + 1, rng);
  for (size_t i = 0; i < radiance.size(); i += 2) {
    const uint32_t bits = uint32_t(rng());
    std::memcpy(&radiance[i], &bits, sizeof(bits));
  }
  // The blurs: rows of any floats, read from an unaligned start (+1), the taps of a 3-row footprint
  // of the widest source; coverage in level-0 texels.
  constexpr size_t kSourceWidth = 2 * kWidth + 1;
  const std::vector<float> rows = AnyFloats((kMaxPyramidFootprint + 2 * kColorPyramidRadius) * (kSourceWidth + 1), rng);
  const float* taps[kMaxPyramidFootprint + 2 * kColorPyramidRadius];
  for (size_t i = 0; i < std::size(taps); ++i) taps[i] = rows.data() + 1 + i * (kSourceWidth + 1);
  std::uniform_int_distribution<int> covered(1, 9);
  std::vector<float> rowCoverage(kMaxPyramidFootprint), columnCoverage(kSourceWidth);
  for (float& c : rowCoverage) c = float(covered(rng));
  for (float& c : columnCoverage) c = float(covered(rng));
  std::vector<float> scratch(kMaxPyramidFootprint * kSourceWidth);
  const size_t targets = test::ForEachSimdTarget([&](const char* target) {
    for (size_t width = 1; width <= kWidth; ++width) {
      CAPTURE(target, width);
      REQUIRE(test::FirstDifferenceOfTwins(width, ColorPyramidSanitizeRowScalar, ColorPyramidSanitizeRowSimd,
                                           radiance.data() + 1, width) == width + 1);
      REQUIRE(test::FirstDifferenceOfTwins(width, ColorPyramidHorizontalRowScalar, ColorPyramidHorizontalRowSimd,
                                           taps[0], width) == width + 1);
      // Even and odd sources (a 3-wide last footprint), and a 1-wide one too where the level is 1 wide.
      for (size_t sourceWidth = width == 1 ? 1 : 2 * width; sourceWidth <= 2 * width + 1; ++sourceWidth) {
        for (size_t footprintRows = 1; footprintRows <= kMaxPyramidFootprint; ++footprintRows) {
          CAPTURE(sourceWidth, footprintRows);
          REQUIRE(test::FirstDifferenceOfTwins(width, ColorPyramidVerticalRowScalar, ColorPyramidVerticalRowSimd, taps,
                                               footprintRows, rowCoverage.data(), columnCoverage.data(), sourceWidth,
                                               width, scratch.data()) == width + 1);
        }
      }
    }
  });
  CHECK(targets >= 1);
}

bool SameLevels(const ColorPyramid& a, const ColorPyramid& b) {
  if (a.levels.size() != b.levels.size()) return false;
  for (size_t k = 0; k < a.levels.size(); ++k) {
    for (size_t c = 0; c < 3; ++c) {
      if (!test::SameBytes(a.levels[k].c[c], b.levels[k].c[c])) return false;
    }
  }
  return true;
}

TEST_CASE("Colour pyramid: the SIMD pass gives the scalar pass's bytes on the default scene and at odd sizes on "
          "every target",
          "[color_pyramid][simd]") {
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> hdr(0.0f, 4.0f);
  std::vector<Plane3<float>> images;
  images.push_back(std::move(test::LoadDefaultScene().Render(1024, 1024).direct.radiance));
  for (const auto& [width, height] : {std::pair<size_t, size_t>{1, 1}, {67, 45}, {1023, 769}}) {
    // HDR radiance with any float at one texel in 16 (the pass sanitises them).
    Plane3<float> radiance = MakePlane3<float>(width, height, 0.0f);
    for (Plane<float>& channel : radiance.c) {
      for (size_t y = 0; y < height; ++y) {
        const std::vector<float> any = AnyFloats(width, rng);
        for (size_t x = 0; x < width; ++x) channel.MutableRow(y)[x] = x % 16 == y % 16 ? any[x] : hdr(rng);
      }
    }
    images.push_back(std::move(radiance));
  }
  for (const Plane3<float>& radiance : images) {
    const auto run = [&](KernelPath kernels) {
      ColorPyramid pyramid;
      RunColorPyramid(radiance, pyramid, kernels);
      return pyramid;
    };
    CAPTURE(radiance.c[0].xsize(), radiance.c[0].ysize());
    CHECK(test::TargetsWhereKernelPathsDiffer(run, SameLevels) == "");
  }
}

}  // namespace
}  // namespace ssgi
