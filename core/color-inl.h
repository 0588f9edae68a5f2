// Highway twins of the 8-bit encoders of core/color.h for the passes' SIMD kernels: the same codes
// as LinearToSrgbCode and UnormCode8 on every target (tests/core/color_simd_test.cpp). Lanes are
// values.
//
// A per-target header in Highway's "-inl.h" convention: a *_simd.cpp includes it after
// hwy/highway.h, once per target through hwy/foreach_target.h, outside any namespace.
#if defined(SSGI_CORE_COLOR_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SSGI_CORE_COLOR_INL_H_
#undef SSGI_CORE_COLOR_INL_H_
#else
#define SSGI_CORE_COLOR_INL_H_
#endif

#include "core/color.h"
#include "core/math-inl.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// BucketCode (core/color.h) in two steps: each lane's bits clamped to the table's range, and its
// bucket; then its code from its bucket's entry.
struct BucketLanes {
  VI bits, bucket;
};

HWY_INLINE BucketLanes BucketsOf(VI bits, const CodeBuckets& buckets) {
  const DI di;
  bits = hn::Min(hn::Max(bits, hn::Set(di, buckets.lowBits)), hn::Set(di, buckets.highBits));
  return {bits, hn::ShiftRight<kCodeBucketShift>(hn::Sub(bits, hn::Set(di, buckets.lowBits)))};
}

HWY_INLINE VI CodeOfEntry(VI bits, VI entry) {
  const DI di;
  // (b & offset mask) - the boundary's offset is negative below the boundary: -1 after the shift.
  const VI below = hn::ShiftRight<31>(
      hn::Sub(hn::And(bits, hn::Set(di, kCodeBucketOffsetMask)), hn::And(entry, hn::Set(di, kCodeEntryOffsetMask))));
  return hn::Add(hn::ShiftRight<kCodeEntryCodeShift>(entry), below);
}

// BucketCode of each lane's bits: one GatherNearIndex of the entries (every table is longer than a
// vector).
HWY_INLINE VI BucketCodeV(VI bits, const CodeBuckets& buckets) {
  const BucketLanes lanes = BucketsOf(bits, buckets);
  const int32_t size = int32_t(buckets.entries.size());
  return CodeOfEntry(lanes.bits, GatherNearIndex(DI(), buckets.entries.data(), size, lanes.bucket));
}

// LinearToSrgbCode: 0 for x <= 0 and NaN; else BucketCodeV of the encoder's buckets
// (SrgbEncodeBuckets()); clamping the bits to their range maps values >= 1 to 255.
HWY_INLINE VI LinearToSrgbCodeV(VF x, const CodeBuckets& encode) {
  const VI code = BucketCodeV(hn::BitCast(DI(), x), encode);
  return hn::IfThenElseZero(hn::RebindMask(DI(), hn::Gt(x, hn::Zero(DF()))), code);
}

// UnormCode8: 0 for x <= 0 and NaN, 255 from 1 on, else x * 255 + 0.5 truncated.
HWY_INLINE VI UnormCode8V(VF x) {
  const DF df;
  const DI di;
  const VI code = hn::ConvertTo(di, hn::Add(hn::Mul(x, hn::Set(df, 255.0f)), hn::Set(df, 0.5f)));
  const VI clamped = hn::IfThenElse(hn::RebindMask(di, hn::Ge(x, hn::Set(df, 1.0f))), hn::Set(di, 255), code);
  return hn::IfThenElseZero(hn::RebindMask(di, hn::Gt(x, hn::Zero(df))), clamped);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#endif  // SSGI_CORE_COLOR_INL_H_
