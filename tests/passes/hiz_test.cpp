#include "passes/hiz.h"

#include <algorithm>
#include <cstring>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "core/gbuffer.h"
#include "core/parallel.h"
#include "core/pyramid.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

// Random view depths in [0.1, 100] m with about one pixel in five background.
Plane<uint32_t> RandomDepth(size_t width, size_t height, std::mt19937& rng) {
  std::uniform_real_distribution<float> depth(0.1f, 100.0f);
  std::uniform_int_distribution<int> background(0, 4);
  Plane<uint32_t> plane = MakePlane<uint32_t>(width, height, 0u);
  for (size_t y = 0; y < height; ++y) {
    for (size_t x = 0; x < width; ++x) {
      const float d = depth(rng);
      plane.MutableRow(y)[x] = PackDepth(background(rng) == 0 ? kBackgroundDepth : d);
    }
  }
  return plane;
}

// The footprint rule written out independently of the pass: [2x, 2x + 1], plus 2x + 2 for the last
// texel of an odd source, never past the source.
struct Span {
  size_t first;
  size_t last;
};
Span Footprint(size_t x, size_t destinationSize, size_t sourceSize) {
  size_t last = 2 * x + 1;
  if (x + 1 == destinationSize && sourceSize % 2 == 1) last = 2 * x + 2;
  return {2 * x, std::min(last, sourceSize - 1)};
}

// The level-0 span covered by texel x of level k, with sizes[k] the level sizes along this axis.
Span Covered(size_t x, size_t k, const std::vector<size_t>& sizes) {
  Span span{x, x};
  for (size_t level = k; level > 0; --level) {
    span = {Footprint(span.first, sizes[level], sizes[level - 1]).first,
            Footprint(span.last, sizes[level], sizes[level - 1]).last};
  }
  return span;
}

TEST_CASE("Hi-Z texels are the exact max of 1/d over the level-0 region they cover, all sizes", "[hiz]") {
  std::mt19937 rng(20240611);
  HiZ hiz;
  for (size_t height = 1; height <= 45; ++height) {
    for (size_t width = 1; width <= 67; ++width) {
      const Plane<uint32_t> depth = RandomDepth(width, height, rng);
      RunHiZ(depth, hiz);

      std::vector<size_t> widths{width};
      std::vector<size_t> heights{height};
      while (widths.back() > 1 || heights.back() > 1) {
        widths.push_back(std::max<size_t>(1, widths.back() / 2));
        heights.push_back(std::max<size_t>(1, heights.back() / 2));
      }
      REQUIRE(hiz.levels.size() == widths.size());

      const Plane<float>& level0 = hiz.levels[0];
      float globalMax = 0.0f;
      for (size_t y = 0; y < height; ++y) {
        for (size_t x = 0; x < width; ++x) {
          const float d = UnpackDepth(depth.ConstRow(y)[x]);
          const float expected = d == kBackgroundDepth ? 0.0f : 1.0f / d;
          REQUIRE(level0.ConstRow(y)[x] == expected);
          globalMax = std::max(globalMax, expected);
        }
      }
      for (size_t k = 0; k < hiz.levels.size(); ++k) {
        const Plane<float>& level = hiz.levels[k];
        REQUIRE(level.xsize() == widths[k]);
        REQUIRE(level.ysize() == heights[k]);
        for (size_t y = 0; y < heights[k]; ++y) {
          const Span rows = Covered(y, k, heights);
          for (size_t x = 0; x < widths[k]; ++x) {
            const Span columns = Covered(x, k, widths);
            float regionMax = 0.0f;
            for (size_t sy = rows.first; sy <= rows.last; ++sy) {
              for (size_t sx = columns.first; sx <= columns.last; ++sx)
                regionMax = std::max(regionMax, level0.ConstRow(sy)[sx]);
            }
            if (level.ConstRow(y)[x] != regionMax) {
              INFO(width << "x" << height << " level " << k << " texel " << x << "," << y);
              REQUIRE(level.ConstRow(y)[x] == regionMax);
            }
          }
        }
      }
      // The top level covers the whole image: every level-0 texel is covered by some texel.
      const Plane<float>& top = hiz.levels.back();
      REQUIRE(top.xsize() == 1);
      REQUIRE(top.ysize() == 1);
      REQUIRE(top.ConstRow(0)[0] == globalMax);
    }
  }
}

TEST_CASE("Hi-Z is identical at 1, 2 and 3 threads and reuses or reshapes its planes", "[hiz]") {
  std::mt19937 rng(7);
  const Plane<uint32_t> depth = RandomDepth(257, 131, rng);
  std::vector<HiZ> results(3);
  for (int threads = 1; threads <= 3; ++threads) {
    const ThreadLimit limit(threads);
    const HiZStats stats = RunHiZ(depth, results[threads - 1]);
    CHECK(stats.texels > 257 * 131);
  }
  for (int i = 1; i < 3; ++i) {
    REQUIRE(results[i].levels.size() == results[0].levels.size());
    for (size_t k = 0; k < results[0].levels.size(); ++k)
      REQUIRE(test::SameBytes(results[i].levels[k], results[0].levels[k]));
  }
  // A smaller frame into the same outputs gets the smaller pyramid.
  RunHiZ(RandomDepth(5, 3, rng), results[0]);
  REQUIRE(results[0].levels.size() == 3);  // 5x3 -> 2x1 -> 1x1
  CHECK(results[0].levels[0].xsize() == 5);
  CHECK(results[0].levels[1].xsize() == 2);
}

TEST_CASE("Hi-Z: the SIMD row kernels equal the scalar definitions on every compiled target", "[hiz][simd]") {
  constexpr size_t kWidth = 70;  // a few vectors of every target, and a tail
  std::mt19937 rng(31);
  const std::vector<float> specials = test::SpecialFloats();
  // Level 0 takes any word: random bits (every kind of NaN among them) and the special values; read
  // from an unaligned start.
  std::vector<uint32_t> words(kWidth + 1);
  for (uint32_t& word : words) word = uint32_t(rng());
  for (size_t i = 0; i < specials.size(); ++i) words[1 + 3 * i % kWidth] = PackDepth(specials[i]);
  // Coarser levels: 1/d, and the special values; footprint rows of the widest source.
  constexpr size_t kSourceWidth = 2 * kWidth + 1;
  std::vector<float> source(kMaxPyramidFootprint * kSourceWidth);
  std::uniform_int_distribution<size_t> pick(0, specials.size() + 3);
  std::uniform_real_distribution<float> inverseDepth(0.0f, 10.0f);
  for (float& texel : source) {
    const size_t i = pick(rng);
    texel = i < specials.size() ? specials[i] : inverseDepth(rng);
  }
  const float* rows[kMaxPyramidFootprint];
  for (size_t r = 0; r < kMaxPyramidFootprint; ++r) rows[r] = source.data() + r * kSourceWidth;
  const size_t targets = test::ForEachSimdTarget([&](const char* target) {
    for (size_t width = 1; width <= kWidth; ++width) {
      CAPTURE(target, width);
      REQUIRE(test::FirstDifferenceOfTwins(width, HiZInverseDepthRowScalar, HiZInverseDepthRowSimd,
                                           words.data() + 1, width) == width + 1);
      // Even and odd sources (a 3-wide last footprint), and a 1-wide one too where the level is 1 wide.
      for (size_t sourceWidth = width == 1 ? 1 : 2 * width; sourceWidth <= 2 * width + 1; ++sourceWidth) {
        for (size_t footprintRows = 1; footprintRows <= kMaxPyramidFootprint; ++footprintRows) {
          CAPTURE(sourceWidth, footprintRows);
          REQUIRE(test::FirstDifferenceOfTwins(width, HiZDownsampleRowScalar, HiZDownsampleRowSimd, rows,
                                               footprintRows, sourceWidth, width) == width + 1);
        }
      }
    }
  });
  CHECK(targets >= 1);
}

bool SameLevels(const HiZ& a, const HiZ& b) {
  if (a.levels.size() != b.levels.size()) return false;
  for (size_t k = 0; k < a.levels.size(); ++k) {
    if (!test::SameBytes(a.levels[k], b.levels[k])) return false;
  }
  return true;
}

TEST_CASE("Hi-Z: the SIMD pass gives the scalar pass's bytes on the default scene and at odd sizes on every target",
          "[hiz][simd]") {
  std::mt19937 rng(5);
  std::vector<Plane<uint32_t>> depths;
  depths.push_back(std::move(test::LoadDefaultScene().Render(1024, 1024).gbuffer.gbuffer.word[GBufferWord::kDepth]));
  for (const auto& [width, height] : {std::pair<size_t, size_t>{1, 1}, {67, 45}, {1023, 769}})
    depths.push_back(RandomDepth(width, height, rng));
  for (const Plane<uint32_t>& depth : depths) {
    const auto run = [&](KernelPath kernels) {
      HiZ hiz;
      RunHiZ(depth, hiz, kernels);
      return hiz;
    };
    CAPTURE(depth.xsize(), depth.ysize());
    CHECK(test::TargetsWhereKernelPathsDiffer(run, SameLevels) == "");
  }
}

}  // namespace
}  // namespace ssgi
