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

// Blocks of pixels as vectors, for a kernel whose cost grows with how many distinct things (such
// as triangles) a vector's pixels meet: pixels near each other in both directions meet fewer than a
// row's (4x4 pixels of the 10k-triangle knot meet 1.69 triangles, 16x1 pixels 2.57). A block is
// BlockWidth wide (4, or the lanes if fewer) and BlockHeight rows tall, its lanes in row order:
// 4x4 with 16 lanes, 4x2 with 8, one row's 4 with 4. (Fixed-size vectors: MaxLanes is the lanes.)
template <class D>
constexpr size_t BlockWidth(D) {
  return HWY_MIN(hn::MaxLanes(D()), size_t(4));
}
template <class D>
constexpr size_t BlockHeight(D) {
  return hn::MaxLanes(D()) / BlockWidth(D());
}

namespace detail {

// The whole block at column x of `rows` (BlockHeight row pointers).
template <class D>
HWY_INLINE hn::Vec<D> LoadWholeBlock(D d, const hn::TFromD<D>* const* rows, size_t x) {
#if HWY_TARGET != HWY_SCALAR  // which has no halves
  if constexpr (BlockHeight(D()) > 1) {
    const hn::Half<D> half;
    return hn::Combine(d, LoadWholeBlock(half, rows + BlockHeight(half), x), LoadWholeBlock(half, rows, x));
  }
#endif
  return hn::LoadU(d, rows[0] + x);
}

template <class D>
HWY_INLINE void StoreWholeBlock(hn::Vec<D> v, D d, hn::TFromD<D>* const* rows, size_t x) {
#if HWY_TARGET != HWY_SCALAR
  if constexpr (BlockHeight(D()) > 1) {
    const hn::Half<D> half;
    StoreWholeBlock(hn::LowerHalf(half, v), half, rows, x);
    StoreWholeBlock(hn::UpperHalf(half, v), half, rows + BlockHeight(half), x);
    return;
  }
#endif
  hn::StoreU(v, d, rows[0] + x);
}

}  // namespace detail

// The block at column x (x < count) of `rows`, BlockHeight row pointers of which the first `rowCount`
// are rows of `count` values; lanes outside them hold `fill`.
template <class D>
HWY_INLINE hn::Vec<D> LoadBlock(D d, const hn::TFromD<D>* const* rows, size_t rowCount, size_t x, size_t count,
                                hn::TFromD<D> fill) {
  constexpr size_t width = BlockWidth(D()), height = BlockHeight(D());
  if (rowCount == height && x + width <= count) return detail::LoadWholeBlock(d, rows, x);
  HWY_ALIGN hn::TFromD<D> buffer[hn::MaxLanes(D())];
  hn::Store(hn::Set(d, fill), d, buffer);
  for (size_t r = 0; r < rowCount; ++r) {
    std::memcpy(buffer + r * width, rows[r] + x, HWY_MIN(width, count - x) * sizeof(hn::TFromD<D>));
  }
  return hn::Load(d, buffer);
}

// Stores v as the block at column x (x < count) of `rows`, as LoadBlock reads it: the lanes that
// fit in the first `rowCount` rows.
template <class D>
HWY_INLINE void StoreBlock(hn::Vec<D> v, D d, hn::TFromD<D>* const* rows, size_t rowCount, size_t x, size_t count) {
  constexpr size_t width = BlockWidth(D()), height = BlockHeight(D());
  if (rowCount == height && x + width <= count) return detail::StoreWholeBlock(v, d, rows, x);
  HWY_ALIGN hn::TFromD<D> buffer[hn::MaxLanes(D())];
  hn::Store(v, d, buffer);
  for (size_t r = 0; r < rowCount; ++r) {
    std::memcpy(rows[r] + x, buffer + r * width, HWY_MIN(width, count - x) * sizeof(hn::TFromD<D>));
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#endif  // SSGI_CORE_ROW_INL_H_
