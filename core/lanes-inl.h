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

// std::clamp(v, lo, hi): v < lo ? lo : hi < v ? hi : v.
template <class V>
V StdClampV(V v, V lo, V hi) {
  return hn::IfThenElse(hn::Lt(v, lo), lo, hn::IfThenElse(hn::Lt(hi, v), hi, v));
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#endif  // SSGI_CORE_LANES_INL_H_
