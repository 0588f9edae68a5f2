// Highway twins of the std:: and glm operations the scalar kernels are written with (docs/design.md §11):
// the same operations in the same order, so every target gives the scalar bits. glm 0.9.9 without
// GLM_FORCE_INTRINSICS computes component by component: dot(a, b) = (a.x b.x + a.y b.y) + a.z b.z,
// length(v) = sqrt(dot(v, v)), normalize(v) = v * (1 / sqrt(dot(v, v))), mix(x, y, a) =
// x (1 - a) + y a. std::min, std::max and std::clamp are comparisons and selects, whose results for
// NaN and signed zeros hn::Min and hn::Max do not reproduce. Lanes are pixels.
//
// A per-target header in Highway's "-inl.h" convention: a *_simd.cpp includes it after
// hwy/highway.h, once per target through hwy/foreach_target.h, outside any namespace.
#if defined(SSGI_CORE_MATH_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SSGI_CORE_MATH_INL_H_
#undef SSGI_CORE_MATH_INL_H_
#else
#define SSGI_CORE_MATH_INL_H_
#endif

#include <algorithm>
#include <cstring>

#include <glm/glm.hpp>

#include "core/color.h"
#include "core/fast_math.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The full-width float vectors the passes' twins work in (lanes are pixels), their integer
// reinterpretations and masks.
using DF = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<DF>;
using DU = hn::RebindToUnsigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;
using MF = hn::Mask<DF>;

// The entries a vector of indices into a table of `size` >= Lanes(d) entries reads, when they lie
// close together: the vector of entries from `first` (where WindowAround or WindowFromLowest puts
// it), and each lane's place in it; `holdsAll` when every lane's entry, and the `reach` entries after
// it, are there (a lane that also reads its index + 1, ..., + reach).
template <class D>
struct GatherWindow {
  int32_t first;
  hn::Vec<hn::RebindToSigned<D>> place;
  bool holdsAll;
};

// The window of the entries from `start` (clamped into the table).
template <class D>
HWY_INLINE GatherWindow<D> WindowAt(D d, int32_t size, int32_t start, hn::Vec<hn::RebindToSigned<D>> index,
                                    int32_t reach) {
  const hn::RebindToSigned<D> di;
  const hn::RebindToUnsigned<D> du;
  const int32_t lanes = int32_t(hn::Lanes(d));
  const int32_t first = std::min(std::max(start, 0), size - lanes);
  const auto place = hn::Sub(index, hn::Set(di, first));
  // Places below 0 wrap above every lane's.
  const bool holdsAll =
      lanes > reach && hn::AllTrue(du, hn::Lt(hn::BitCast(du, place), hn::Set(du, uint32_t(lanes - reach))));
  return {first, place, holdsAll};
}

// The window centred on lane 0's index: for indices scattered a little around it.
template <class D>
HWY_INLINE GatherWindow<D> WindowAround(D d, int32_t size, hn::Vec<hn::RebindToSigned<D>> index,
                                        int32_t reach = 0) {
  return WindowAt(d, size, hn::GetLane(index) - int32_t(hn::Lanes(d)) / 2, index, reach);
}

// WindowAround starting at the lowest lane's index: for indices that rise or fall along the lanes
// (a smooth quantity across neighbouring pixels), whose spread may then be Lanes(d) - 1 - reach
// whichever way they run.
template <class D>
HWY_INLINE GatherWindow<D> WindowFromLowest(D d, int32_t size, hn::Vec<hn::RebindToSigned<D>> index,
                                            int32_t reach = 0) {
  return WindowAt(d, size, hn::GetLane(hn::MinOfLanes(hn::RebindToSigned<D>(), index)), index, reach);
}

// The entries of a window that holds all of them: one load and one in-register lookup.
template <class D>
HWY_INLINE hn::Vec<D> LookupInWindow(D d, const hn::TFromD<D>* table, const GatherWindow<D>& window) {
  return hn::TableLookupLanes(hn::LoadU(d, table + window.first), hn::IndicesFromVec(d, window.place));
}

// GatherIndex(d, table, index) for a table of `size` >= Lanes(d) entries. Neighbouring pixels
// mostly read nearby entries: when their window holds them all, they come from LookupInWindow,
// several times cheaper than a gather (a 16-lane gather takes about 24 cycles on Zen 5). Both read
// the same entries, so the values do not depend on the path.
template <class D>
HWY_INLINE hn::Vec<D> GatherNearIndex(D d, const hn::TFromD<D>* table, int32_t size,
                                      hn::Vec<hn::RebindToSigned<D>> index) {
  const GatherWindow<D> window = WindowAround(d, size, index);
  return window.holdsAll ? LookupInWindow(d, table, window) : hn::GatherIndex(d, table, index);
}

// GatherNearIndex of three index vectors into one table, with one branch: mostly all three windows
// hold their lanes (the R, G and B codes of neighbouring pixels).
template <class D>
HWY_INLINE void GatherNearIndex3(D d, const hn::TFromD<D>* table, int32_t size,
                                 const hn::Vec<hn::RebindToSigned<D>> (&index)[3], hn::Vec<D> (&value)[3]) {
  const GatherWindow<D> window[3] = {WindowAround(d, size, index[0]), WindowAround(d, size, index[1]),
                                     WindowAround(d, size, index[2])};
  if (window[0].holdsAll & window[1].holdsAll & window[2].holdsAll) {
    for (int c = 0; c < 3; ++c) value[c] = LookupInWindow(d, table, window[c]);
    return;
  }
  for (int c = 0; c < 3; ++c)
    value[c] = window[c].holdsAll ? LookupInWindow(d, table, window[c]) : hn::GatherIndex(d, table, index[c]);
}

// GatherIndex(d, table, index) for a table of 256 floats (indices in [0, 256), as 8-bit codes are):
// with 16 lanes of AVX-512, eight two-vector permutes and a tree of selects on the index's top three
// bits, without touching memory per lane (3.3x a gather's throughput on Zen 5); elsewhere a gather.
template <class D>
HWY_INLINE hn::Vec<D> LookupTable256(D d, const float* HWY_RESTRICT table, hn::Vec<hn::RebindToSigned<D>> index) {
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
  if constexpr (hn::MaxLanes(D()) == 16) {
    const hn::RebindToSigned<D> di;
    hn::Vec<D> pair[8];
    for (int k = 0; k < 8; ++k) {
      // The permute reads the low 5 bits of each lane: entries 32k to 32k + 31.
      pair[k] = hn::Vec<D>{_mm512_permutex2var_ps(hn::LoadU(d, table + 32 * k).raw, index.raw,
                                                  hn::LoadU(d, table + 32 * k + 16).raw)};
    }
    for (int bit = 5, count = 8; bit < 8; ++bit, count /= 2) {
      const auto upper = hn::RebindMask(d, hn::TestBit(index, hn::Set(di, 1 << bit)));
      for (int k = 0; k < count / 2; ++k) pair[k] = hn::IfThenElse(upper, pair[2 * k + 1], pair[2 * k]);
    }
    return pair[0];
  }
#endif
  return hn::GatherIndex(d, table, index);
}

// GatherIndex(d, table, index) for a table of kMaxEntries 32-bit entries: where a vector holds them
// all, one in-register lookup.
template <size_t kMaxEntries, class D>
HWY_INLINE hn::Vec<D> LookupSmallTable(D d, const hn::TFromD<D>* HWY_RESTRICT table,
                                       hn::Vec<hn::RebindToSigned<D>> index) {
  if constexpr (hn::MaxLanes(D()) == kMaxEntries) {
    return hn::TableLookupLanes(hn::LoadU(d, table), hn::IndicesFromVec(d, index));
  } else {
    return hn::GatherIndex(d, table, index);
  }
}

// The lanes of `mask` as the bits of a word, lane i at bit i (vectors of at most 64 lanes): for
// loops over the set lanes.
template <class D>
HWY_INLINE uint64_t LaneBits(D d, hn::Mask<D> mask) {
  uint8_t bytes[8] = {};
  hn::StoreMaskBits(d, mask, bytes);
  uint64_t bits;
  std::memcpy(&bits, bytes, sizeof(bits));
  constexpr size_t kMaxLanes = hn::MaxLanes(D());
  static_assert(kMaxLanes <= 64);
  return hn::Lanes(d) < 64 ? bits & ((uint64_t(1) << hn::Lanes(d)) - 1) : bits;
}

// A glm::vec3 per pixel: a vector per component.
template <class D>
struct Vec3V {
  hn::Vec<D> x, y, z;
};

// The same vec3 in every lane.
template <class D>
Vec3V<D> Set3(D d, const glm::vec3& v) {
  return {hn::Set(d, v.x), hn::Set(d, v.y), hn::Set(d, v.z)};
}

// std::min(a, b) = b < a ? b : a.
template <class V>
V MinStd(V a, V b) {
  return hn::IfThenElse(hn::Lt(b, a), b, a);
}

// std::max(a, b) = a < b ? b : a.
template <class V>
V MaxStd(V a, V b) {
  return hn::IfThenElse(hn::Lt(a, b), b, a);
}

// SanitizeRadiance (core/color.h).
template <class V>
V SanitizeRadianceV(V v) {
  const hn::DFromV<V> d;
  return hn::IfThenElseZero(hn::Gt(v, hn::Zero(d)), MinStd(v, hn::Set(d, kMaxRadiance)));
}

// std::clamp(v, lo, hi) = v < lo ? lo : (hi < v ? hi : v).
template <class V>
V ClampStd(V v, V lo, V hi) {
  return hn::IfThenElse(hn::Lt(v, lo), lo, hn::IfThenElse(hn::Lt(hi, v), hi, v));
}

template <class D>
Vec3V<D> Add3(const Vec3V<D>& a, const Vec3V<D>& b) {
  return {hn::Add(a.x, b.x), hn::Add(a.y, b.y), hn::Add(a.z, b.z)};
}

template <class D>
Vec3V<D> Sub3(const Vec3V<D>& a, const Vec3V<D>& b) {
  return {hn::Sub(a.x, b.x), hn::Sub(a.y, b.y), hn::Sub(a.z, b.z)};
}

// Component by component, as glm's vec3 * vec3.
template <class D>
Vec3V<D> Mul3(const Vec3V<D>& a, const Vec3V<D>& b) {
  return {hn::Mul(a.x, b.x), hn::Mul(a.y, b.y), hn::Mul(a.z, b.z)};
}

// glm's vec3 * float.
template <class D>
Vec3V<D> Scale3(const Vec3V<D>& v, hn::Vec<D> s) {
  return {hn::Mul(v.x, s), hn::Mul(v.y, s), hn::Mul(v.z, s)};
}

// glm's vec3 / float: three divisions.
template <class D>
Vec3V<D> Div3(const Vec3V<D>& v, hn::Vec<D> s) {
  return {hn::Div(v.x, s), hn::Div(v.y, s), hn::Div(v.z, s)};
}

template <class D>
Vec3V<D> Neg3(const Vec3V<D>& v) {
  return {hn::Neg(v.x), hn::Neg(v.y), hn::Neg(v.z)};
}

template <class D, class M>
Vec3V<D> IfThenElse3(M mask, const Vec3V<D>& yes, const Vec3V<D>& no) {
  return {hn::IfThenElse(mask, yes.x, no.x), hn::IfThenElse(mask, yes.y, no.y), hn::IfThenElse(mask, yes.z, no.z)};
}

template <class D>
hn::Vec<D> Dot3(const Vec3V<D>& a, const Vec3V<D>& b) {
  return hn::Add(hn::Add(hn::Mul(a.x, b.x), hn::Mul(a.y, b.y)), hn::Mul(a.z, b.z));
}

template <class D>
hn::Vec<D> Length3(const Vec3V<D>& v) {
  return hn::Sqrt(Dot3(v, v));
}

template <class D>
Vec3V<D> Normalize3(D d, const Vec3V<D>& v) {
  return Scale3(v, hn::Div(hn::Set(d, 1.0f), Length3(v)));
}

// glm::cross(a, b): (a.y b.z - b.y a.z, a.z b.x - b.z a.x, a.x b.y - b.x a.y).
template <class D>
Vec3V<D> Cross3(const Vec3V<D>& a, const Vec3V<D>& b) {
  return {hn::Sub(hn::Mul(a.y, b.z), hn::Mul(b.y, a.z)), hn::Sub(hn::Mul(a.z, b.x), hn::Mul(b.z, a.x)),
          hn::Sub(hn::Mul(a.x, b.y), hn::Mul(b.x, a.y))};
}

// glm's mat3 * vec3: row r is (m[0][r] v.x + m[1][r] v.y) + m[2][r] v.z.
template <class D>
Vec3V<D> MulMat3(D d, const glm::mat3& m, const Vec3V<D>& v) {
  return Add3(Add3(Scale3(Set3(d, m[0]), v.x), Scale3(Set3(d, m[1]), v.y)), Scale3(Set3(d, m[2]), v.z));
}

// glm::mix(x, y, a) with a scalar a per pixel.
template <class D>
Vec3V<D> Mix3(D d, const Vec3V<D>& x, const Vec3V<D>& y, hn::Vec<D> a) {
  return Add3(Scale3(x, hn::Sub(hn::Set(d, 1.0f), a)), Scale3(y, a));
}

// AcosPoly (core/fast_math.h) per lane: the same Horner steps, square root and select.
template <class V>
V AcosPolyV(V x) {
  const hn::DFromV<V> d;
  const V a = hn::Abs(x);
  V p = hn::Add(hn::Mul(hn::Set(d, kAcosA3), a), hn::Set(d, kAcosA2));
  p = hn::Add(hn::Mul(p, a), hn::Set(d, kAcosA1));
  p = hn::Add(hn::Mul(p, a), hn::Set(d, kAcosA0));
  const V r = hn::Mul(p, hn::Sqrt(hn::Sub(hn::Set(d, 1.0f), a)));
  return hn::IfThenElse(hn::Lt(x, hn::Zero(d)), hn::Sub(hn::Set(d, kPiFloat), r), r);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#endif  // SSGI_CORE_MATH_INL_H_
