// Rows of a plane, a vector at a time, for the passes' SIMD kernels: the last vector of a row whose
// width is not a multiple of the vector length goes through a vector-sized buffer, so a kernel runs
// its one vector body on every pixel and never touches memory past the row's end.
//
// A per-target header in Highway's "-inl.h" convention: a *_simd.cpp includes it after
// hwy/highway.h, once per target through hwy/foreach_target.h, outside any namespace.
#if defined(SSGI_CORE_ROW_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SSGI_CORE_ROW_INL_H_
#undef SSGI_CORE_ROW_INL_H_
#else
#define SSGI_CORE_ROW_INL_H_
#endif

#include <cstdint>
#include <cstring>

#include "core/math-inl.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Values x, x + 1, ... of a row of `count` values (x < count); lanes past its end hold `fill`.
template <class D>
HWY_INLINE hn::Vec<D> LoadRow(D d, const hn::TFromD<D>* row, size_t x, size_t count, hn::TFromD<D> fill) {
  if (x + hn::Lanes(d) <= count) return hn::LoadU(d, row + x);
  HWY_ALIGN hn::TFromD<D> buffer[HWY_MAX_BYTES / sizeof(hn::TFromD<D>)];
  hn::Store(hn::Set(d, fill), d, buffer);
  std::memcpy(buffer, row + x, (count - x) * sizeof(hn::TFromD<D>));
  return hn::Load(d, buffer);
}

// Stores v at x, x + 1, ... of a row of `count` values (x < count), the lanes that fit.
template <class D>
HWY_INLINE void StoreRow(hn::Vec<D> v, D d, hn::TFromD<D>* row, size_t x, size_t count) {
  if (x + hn::Lanes(d) <= count) return hn::StoreU(v, d, row + x);
  HWY_ALIGN hn::TFromD<D> buffer[HWY_MAX_BYTES / sizeof(hn::TFromD<D>)];
  hn::Store(v, d, buffer);
  std::memcpy(row + x, buffer, (count - x) * sizeof(hn::TFromD<D>));
}

// LoadRow of three channel rows (fill 0).
template <class D>
HWY_INLINE Vec3V<D> LoadRow3(D d, const float* const rows[3], size_t x, size_t count) {
  return {LoadRow(d, rows[0], x, count, 0.0f), LoadRow(d, rows[1], x, count, 0.0f),
          LoadRow(d, rows[2], x, count, 0.0f)};
}

// StoreRow of three channel rows.
template <class D>
HWY_INLINE void StoreRow3(const Vec3V<D>& v, D d, float* const rows[3], size_t x, size_t count) {
  StoreRow(v.x, d, rows[0], x, count);
  StoreRow(v.y, d, rows[1], x, count);
  StoreRow(v.z, d, rows[2], x, count);
}

// StoreRow3 with non-temporal stores where a whole vector fits at an aligned address (as in the
// planes' rows, core/plane.h, from a multiple of the lanes), so a pass whose outputs are not read
// back soon writes them without first reading their lines in. Weakly ordered: the kernel ends with
// hwy::FlushStream() before another thread may read the rows.
template <class D>
HWY_INLINE void StreamRow3(const Vec3V<D>& v, D d, float* const rows[3], size_t x, size_t count) {
  const uintptr_t vectorBytes = hn::Lanes(d) * sizeof(float);
  const auto misaligned = [&](int c) { return reinterpret_cast<uintptr_t>(rows[c] + x) % vectorBytes; };
  if (x + hn::Lanes(d) > count || (misaligned(0) | misaligned(1) | misaligned(2)) != 0) {
    return StoreRow3(v, d, rows, x, count);
  }
  hn::Stream(v.x, d, rows[0] + x);
  hn::Stream(v.y, d, rows[1] + x);
  hn::Stream(v.z, d, rows[2] + x);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#endif  // SSGI_CORE_ROW_INL_H_
