// The Highway twin of TonemapRowScalar (tonemap.cpp): the exposure product as the scalar kernel
// rounds it, then each channel's code from the curve's bucket table (TonemapCodeBuckets): the three
// channels' entries from one GatherNearIndex3 (core/math-inl.h), so every target gives the scalar
// bytes (tests/passes/tonemap_test.cpp checks each compiled target and every float).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/tonemap_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "core/color-inl.h"
#include "passes/tonemap.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The buckets of one channel of a vector of pixels: TonemapCodeBuckets' lookup of x * scale, which
// is TonemapCode for every product >= 0 that is not NaN (NaN is 0 there).
HWY_INLINE BucketLanes TonemapBuckets(VF x, VF scale, const CodeBuckets& buckets) {
  x = hn::Mul(x, scale);
  x = hn::IfThenElseZero(hn::Eq(x, x), x);  // NaN -> 0
  return BucketsOf(hn::BitCast(DI(), x), buckets);
}

// Stores the pixels' codes as interleaved R, G, B bytes, 3 per lane. Each pixel's codes go into one
// 32-bit lane (R, G, B, 0), a byte shuffle packs each 16-byte block's four pixels into its first 12
// bytes, and a lane compress drops every block's fourth lane: a few operations instead of narrowing
// each channel to bytes and interleaving them.
HWY_INLINE void StoreRgb(hn::Vec<DU> r, hn::Vec<DU> g, hn::Vec<DU> b, uint8_t* rgb) {
#if HWY_TARGET == HWY_SCALAR
  const hn::Rebind<uint8_t, DU> du8;
  hn::StoreInterleaved3(hn::DemoteTo(du8, r), hn::DemoteTo(du8, g), hn::DemoteTo(du8, b), du8, rgb);
#else
  const DU du;
  const hn::Repartition<uint8_t, DU> du8;
  const auto pixels = hn::Or(hn::Or(r, hn::ShiftLeft<8>(g)), hn::ShiftLeft<16>(b));
  alignas(16) static constexpr uint8_t kPackBlock[16] = {0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, 3, 7, 11, 15};
  const auto packed = hn::TableLookupBytes(hn::BitCast(du8, pixels), hn::LoadDup128(du8, kPackBlock));
  const auto firstThreeOfBlock = hn::Ne(hn::And(hn::Iota(du, 0), hn::Set(du, 3u)), hn::Set(du, 3u));
  const size_t words = hn::Lanes(du) / 4 * 3;
  hn::BlendedStore(hn::Compress(hn::BitCast(du, packed), firstThreeOfBlock), hn::FirstN(du, words), du,
                   reinterpret_cast<uint32_t*>(rgb));
#endif
}

void TonemapRow(const float* const radiance[3], size_t count, float scale, Tonemap curve, uint8_t* rgb) {
  const DF df;
  const DI di;
  const CodeBuckets& buckets = TonemapCodeBuckets(curve);
  const int32_t* entries = buckets.entries.data();
  const int32_t size = int32_t(buckets.entries.size());
  const size_t lanes = hn::Lanes(df);
  const auto scaleV = hn::Set(df, scale);
  size_t i = 0;
  for (; i + lanes <= count; i += lanes) {
    const BucketLanes channel[3] = {TonemapBuckets(hn::LoadU(df, radiance[0] + i), scaleV, buckets),
                                    TonemapBuckets(hn::LoadU(df, radiance[1] + i), scaleV, buckets),
                                    TonemapBuckets(hn::LoadU(df, radiance[2] + i), scaleV, buckets)};
    VI entry[3];
    GatherNearIndex3(di, entries, size, {channel[0].bucket, channel[1].bucket, channel[2].bucket}, entry);
    const auto code = [&](int c) { return hn::BitCast(DU(), CodeOfEntry(channel[c].bits, entry[c])); };
    StoreRgb(code(0), code(1), code(2), rgb + 3 * i);
  }
  const float* const tail[3] = {radiance[0] + i, radiance[1] + i, radiance[2] + i};
  TonemapRowScalar(tail, count - i, scale, curve, rgb + 3 * i);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(TonemapRow);

void TonemapRowSimd(const float* const radiance[3], size_t count, float scale, Tonemap curve, uint8_t* rgb) {
  HWY_DYNAMIC_DISPATCH(TonemapRow)(radiance, count, scale, curve, rgb);
}

}  // namespace ssgi
#endif
