// TileMask and ForEachTileRun (core/tile_mask.h): a row split into runs of alike tiles covers every
// pixel exactly once, the last tile cut at the image's edge.
#include "core/tile_mask.h"

#include <catch2/catch.hpp>

#include <random>
#include <vector>

namespace ssgi {
namespace {

TEST_CASE("tile mask: a row's runs cover each pixel once, as the mask says", "[tiles]") {
  std::mt19937 rng(3);
  for (const int width : {1, 31, 32, 33, 95, 96, 100, 1023}) {
    for (const int height : {1, 40, 64}) {
      TileMask mask = TileMask::None(width, height);
      CHECK(mask.Fits(width, height));
      CHECK_FALSE(mask.Fits(width + TileMask::kTileSize, height));
      for (uint8_t& tile : mask.needed) tile = uint8_t(rng() % 2);
      for (const int y : {0, height / 2, height - 1}) {
        std::vector<int> visits(size_t(width), 0);
        std::vector<int> kind(size_t(width), -1);
        int previousEnd = 0, previousKind = -1;
        const auto visit = [&](int k) {
          return [&, k](int xBegin, int xEnd) {
            CHECK(xBegin == previousEnd);  // in order, no gap
            CHECK(xBegin < xEnd);
            CHECK(k != previousKind);  // runs of alike tiles are merged
            previousEnd = xEnd;
            previousKind = k;
            for (int x = xBegin; x < xEnd; ++x) {
              ++visits[size_t(x)];
              kind[size_t(x)] = k;
            }
          };
        };
        ForEachTileRun(&mask, y, width, visit(1), visit(0));
        CAPTURE(width, height, y);
        CHECK(previousEnd == width);
        for (int x = 0; x < width; ++x) {
          CHECK(visits[size_t(x)] == 1);
          CHECK(kind[size_t(x)] == int(mask.Needed(x / TileMask::kTileSize, y / TileMask::kTileSize)));
        }
      }
    }
  }
}

TEST_CASE("tile mask: without a mask the row is one run", "[tiles]") {
  int runs = 0;
  ForEachTileRun(
      nullptr, 5, 77,
      [&](int xBegin, int xEnd) {
        CHECK(xBegin == 0);
        CHECK(xEnd == 77);
        ++runs;
      },
      [&](int, int) { FAIL("nothing is skipped without a mask"); });
  CHECK(runs == 1);
}

}  // namespace
}  // namespace ssgi
