#include "passes/hiz.h"

#include <algorithm>
#include <cstring>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "core/gbuffer.h"
#include "core/parallel.h"

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
    for (size_t k = 0; k < results[0].levels.size(); ++k) {
      const Plane<float>& a = results[0].levels[k];
      const Plane<float>& b = results[i].levels[k];
      for (size_t y = 0; y < a.ysize(); ++y)
        REQUIRE(std::memcmp(a.ConstRow(y), b.ConstRow(y), a.xsize() * sizeof(float)) == 0);
    }
  }
  // A smaller frame into the same outputs gets the smaller pyramid.
  RunHiZ(RandomDepth(5, 3, rng), results[0]);
  REQUIRE(results[0].levels.size() == 3);  // 5x3 -> 2x1 -> 1x1
  CHECK(results[0].levels[0].xsize() == 5);
  CHECK(results[0].levels[1].xsize() == 2);
}

}  // namespace
}  // namespace ssgi
