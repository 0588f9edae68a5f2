// Lane helpers of the passes' SIMD kernels: the twins of the C++ operations the scalar kernels use
// whose Highway counterparts differ (DESIGN.md §11). std::min / std::max / std::clamp keep their
// first operand when comparisons fail (NaN) or tie (-0 vs +0), where hn::Min / hn::Max follow the
// target's instruction. Lanes are pixels.
//
// A per-target header in Highway's "-inl.h" convention: a *_simd.cpp includes it after
// hwy/highway.h, once per target through hwy/foreach_target.h, outside any namespace.
#if defined(SSGI_CORE_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SSGI_CORE_LANES_INL_H_
#undef SSGI_CORE_LANES_INL_H_
#else
#define SSGI_CORE_LANES_INL_H_
#endif

#include <algorithm>
#include <cstddef>

#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// std::min(a, b): b < a ? b : a.
template <class V>
V StdMinV(V a, V b) {
  return hn::IfThenElse(hn::Lt(b, a), b, a);
}

// std::max(a, b): a < b ? b : a.
template <class V>
V StdMaxV(V a, V b) {
  return hn::IfThenElse(hn::Lt(a, b), b, a);
}

// std::clamp(v, lo, hi): v < lo ? lo : hi < v ? hi : v.
template <class V>
V StdClampV(V v, V lo, V hi) {
  return hn::IfThenElse(hn::Lt(v, lo), lo, hn::IfThenElse(hn::Lt(hi, v), hi, v));
}

// The first `count` (<= Lanes(d)) elements from p, the other lanes 0: a whole vector, or element by
// element so that a partial vector never reads past the end of a row segment.
template <class D>
hn::Vec<D> LoadFirstLanes(D d, const hn::TFromD<D>* p, size_t count) {
  if (count == hn::Lanes(d)) return hn::LoadU(d, p);
  HWY_ALIGN hn::TFromD<D> lanes[hn::MaxLanes(D())] = {};
  std::copy(p, p + count, lanes);
  return hn::Load(d, lanes);
}

// Stores the first `count` (<= Lanes(d)) lanes of v at p: a whole vector, or lane by lane so that a
// partial vector never writes past the end of a row segment (which another thread may own).
template <class D>
void StoreFirstLanes(D d, hn::Vec<D> v, size_t count, hn::TFromD<D>* p) {
  if (count == hn::Lanes(d)) return hn::StoreU(v, d, p);
  HWY_ALIGN hn::TFromD<D> lanes[hn::MaxLanes(D())];
  hn::Store(v, d, lanes);
  std::copy(lanes, lanes + count, p);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#endif  // SSGI_CORE_LANES_INL_H_
