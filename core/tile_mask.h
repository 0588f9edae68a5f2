// Which 32x32 tiles of an image need an effect: the frame plan (passes/frame/plan.h) classifies the
// tiles once, and every pass that can skip work runs its kernel on the needed tiles' pixels only,
// storing elsewhere what its kernel would store there (docs/design.md §9: cost follows need).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ssgi {

struct TileMask {
  static constexpr int kTileSize = 32;

  int tilesX = 0, tilesY = 0;
  std::vector<uint8_t> needed;  // tilesX * tilesY, row-major: 1 where the tile needs the effect

  // All tiles of a width x height image, none needed.
  static TileMask None(int width, int height) {
    TileMask mask;
    mask.tilesX = (width + kTileSize - 1) / kTileSize;
    mask.tilesY = (height + kTileSize - 1) / kTileSize;
    mask.needed.assign(size_t(mask.tilesX) * size_t(mask.tilesY), 0);
    return mask;
  }
  bool Needed(int tileX, int tileY) const { return needed[size_t(tileY) * size_t(tilesX) + size_t(tileX)] != 0; }
  bool Fits(int width, int height) const {
    return tilesX == (width + kTileSize - 1) / kTileSize && tilesY == (height + kTileSize - 1) / kTileSize;
  }
};

// Splits row y of a `width`-pixel image into runs of alike tiles: run(xBegin, xEnd) for each run of
// needed tiles, skip(xBegin, xEnd) for each run of the others. Without a mask, run(0, width).
template <class Run, class Skip>
void ForEachTileRun(const TileMask* mask, int y, int width, const Run& run, const Skip& skip) {
  if (mask == nullptr) return run(0, width);
  const int tileY = y / TileMask::kTileSize;
  int begin = 0;
  while (begin < width) {
    const bool needed = mask->Needed(begin / TileMask::kTileSize, tileY);
    int end = begin;
    while (end < width && mask->Needed(end / TileMask::kTileSize, tileY) == needed) end += TileMask::kTileSize;
    if (end > width) end = width;
    if (needed) run(begin, end);
    else skip(begin, end);
    begin = end;
  }
}

}  // namespace ssgi
