// The Highway twins of std::min, std::max, std::clamp and glm's dot, length, normalize and mix
// (core/math-inl.h), bit for bit, on every compiled and supported target: NaN, signed zeros and
// infinities, where hn::Min and hn::Max would differ, and random vectors.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tests/core/math_simd_test.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "core/math-inl.h"
#include "core/row-inl.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<float>;

// in: a, b, c; out: MinStd(a, b), MaxStd(a, b), ClampStd(a, b, c).
void MinMaxClamp(const float* const* in, size_t count, float* const* out) {
  const D d;
  for (size_t x = 0; x < count; x += hn::Lanes(d)) {
    const auto a = LoadRow(d, in[0], x, count, 0.0f);
    const auto b = LoadRow(d, in[1], x, count, 0.0f);
    StoreRow(MinStd(a, b), d, out[0], x, count);
    StoreRow(MaxStd(a, b), d, out[1], x, count);
    StoreRow(ClampStd(a, b, LoadRow(d, in[2], x, count, 0.0f)), d, out[2], x, count);
  }
}

// in: u, v (three rows each), t; out: dot(u, v), length(u), normalize(u), mix(u, v, t).
void VectorOps(const float* const* in, size_t count, float* const* out) {
  const D d;
  for (size_t x = 0; x < count; x += hn::Lanes(d)) {
    const Vec3V<D> u = LoadRow3(d, in, x, count), v = LoadRow3(d, in + 3, x, count);
    StoreRow(Dot3(u, v), d, out[0], x, count);
    StoreRow(Length3(u), d, out[1], x, count);
    StoreRow3(Normalize3(d, u), d, out + 2, x, count);
    StoreRow3(Mix3(d, u, v, LoadRow(d, in[6], x, count, 0.0f)), d, out + 5, x, count);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "tests/simd_rows.h"

namespace ssgi {
HWY_EXPORT(MinMaxClamp);
HWY_EXPORT(VectorOps);

namespace {

TEST_CASE("math: MinStd, MaxStd, ClampStd equal std::min, std::max, std::clamp on every target", "[math][simd]") {
  const float inf = std::numeric_limits<float>::infinity();
  const float specials[] = {std::nanf(""), -0.0f, 0.0f, -inf, inf, -1.0f, 0.5f, 1.0f, 1e-40f};
  // Every triple (a, b, c) of special values whose clamp bounds b, c are not out of order (std::clamp's
  // precondition; NaN bounds included).
  std::vector<glm::vec3> triples;
  for (float a : specials)
    for (float b : specials)
      for (float c : specials)
        if (!(c < b)) triples.push_back({a, b, c});
  const size_t count = triples.size();
  test::SimdRows in(3, count), expected(3, count);
  for (size_t i = 0; i < count; ++i) {
    const glm::vec3 t = triples[i];
    in.Set3(0, i, t);
    expected.Set3(0, i, {std::min(t.x, t.y), std::max(t.x, t.y), std::clamp(t.x, t.y, t.z)});
  }
  test::CheckEveryTarget(expected, count, [&](float* const* out) {
    HWY_DYNAMIC_DISPATCH(MinMaxClamp)(in.in.data(), count, out);
  });
}

TEST_CASE("math: Dot3, Length3, Normalize3, Mix3 equal glm on every target", "[math][simd]") {
  constexpr size_t kCount = 10001;
  std::mt19937 rng(15);
  std::uniform_real_distribution<float> wide(-100.0f, 100.0f), unit(0.0f, 1.0f);
  test::SimdRows in(7, kCount), expected(8, kCount);
  for (size_t i = 0; i < kCount; ++i) {
    const glm::vec3 u(wide(rng), wide(rng), i % 5 == 0 ? -0.0f : wide(rng));
    const glm::vec3 v = test::RandomUnitVector(rng);
    const float t = unit(rng);
    in.Set3(0, i, u);
    in.Set3(3, i, v);
    in.values[6][i] = t;
    expected.values[0][i] = glm::dot(u, v);
    expected.values[1][i] = glm::length(u);
    expected.Set3(2, i, glm::normalize(u));
    expected.Set3(5, i, glm::mix(u, v, t));
  }
  test::CheckEveryTarget(expected, kCount, [&](float* const* out) {
    HWY_DYNAMIC_DISPATCH(VectorOps)(in.in.data(), kCount, out);
  });
}

}  // namespace
}  // namespace ssgi
#endif
