// The Highway twin of CountPlanRowScalar (passes/frame/plan.cpp): lanes are the pixels of a tile's part of
// the row, counted with masks. Counts are integers, so every target gives the scalar counts
// (tests/passes/frame/plan_test.cpp checks each compiled target).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/frame/plan_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "core/row-inl.h"
#include "passes/frame/plan.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace {

void CountPlanRow(const uint32_t* word1, const uint32_t* word2, int width, uint32_t smoothCodes, uint32_t* geometry,
                  uint32_t* smooth) {
  const DU du;
  const size_t count = size_t(width);
  const auto background = hn::Set(du, PackDepth(kBackgroundDepth));
  const auto codes = hn::Set(du, smoothCodes);
  // Vectors (at most 16 lanes) divide the tile: none straddles two tiles.
  for (size_t begin = 0, tile = 0; begin < count; begin += TileMask::kTileSize, ++tile) {
    const size_t end = std::min(begin + TileMask::kTileSize, count);
    size_t covered = 0, below = 0;
    for (size_t x = begin; x < end; x += hn::Lanes(du)) {
      const auto drawn = hn::Ne(LoadRow(du, word2, x, end, PackDepth(kBackgroundDepth)), background);
      const auto rough = hn::ShiftRight<24>(LoadRow(du, word1, x, end, 0u));
      covered += hn::CountTrue(du, drawn);
      below += hn::CountTrue(du, hn::And(drawn, hn::Lt(rough, codes)));
    }
    geometry[tile] += uint32_t(covered);
    smooth[tile] += uint32_t(below);
  }
}

}  // namespace
}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(CountPlanRow);

void CountPlanRowSimd(const uint32_t* word1, const uint32_t* word2, int width, uint32_t smoothCodes,
                      uint32_t* geometry, uint32_t* smooth) {
  HWY_DYNAMIC_DISPATCH(CountPlanRow)(word1, word2, width, smoothCodes, geometry, smooth);
}

}  // namespace ssgi
#endif
