// AcosPoly (core/fast_math.h): its error against acos in double over the floats of [-1, 1], and its
// Highway twin AcosPolyV (core/math-inl.h) bit for bit on every compiled and supported target.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tests/core/fast_math_test.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "core/math-inl.h"
#include "core/row-inl.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// in: x; out: AcosPolyV(x).
void Acos(const float* const* in, size_t count, float* const* out) {
  const hn::ScalableTag<float> d;
  for (size_t x = 0; x < count; x += hn::Lanes(d))
    StoreRow(AcosPolyV(LoadRow(d, in[0], x, count, 0.0f)), d, out[0], x, count);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/fast_math.h"
#include "tests/simd_rows.h"

namespace ssgi {
HWY_EXPORT(Acos);

namespace {

// Every 256th float of [0, 1] by bit pattern and its negation, and the ends and zeros exactly.
std::vector<float> FloatsOfUnitInterval() {
  std::vector<float> values;
  const uint32_t one = std::bit_cast<uint32_t>(1.0f);
  for (uint32_t bits = 0; bits <= one; bits += 256) {
    values.push_back(std::bit_cast<float>(bits));
    values.push_back(-std::bit_cast<float>(bits));
  }
  for (const float end : {1.0f, -1.0f, 0.0f, -0.0f}) values.push_back(end);
  return values;
}

TEST_CASE("fast math: AcosPoly is within 6.8e-5 rad of acos on [-1, 1], in [0, pi], exact at 1", "[fast_math]") {
  double worst = 0.0, worstAt = 0.0;
  size_t outOfRange = 0;
  for (const float x : FloatsOfUnitInterval()) {
    const float a = AcosPoly(x);
    if (!(a >= 0.0f && a <= kPiFloat)) ++outOfRange;
    const double error = std::fabs(double(a) - std::acos(double(x)));
    if (error > worst) worst = error, worstAt = x;
  }
  // Abramowitz & Stegun quote 5e-5 for 4.4.45; its printed coefficients err by 6.75e-5 at 0 (in
  // exact arithmetic), 6.77e-5 with float32's roundings.
  CAPTURE(worst, worstAt);
  CHECK(outOfRange == 0);
  CHECK(worst < 6.8e-5);
  CHECK(worst > 6.7e-5);
  CHECK(std::fabs(worstAt) < 1e-3);
  CHECK(AcosPoly(1.0f) == 0.0f);
  CHECK(AcosPoly(-1.0f) == kPiFloat);
}

TEST_CASE("fast math: AcosPolyV equals AcosPoly on every target", "[fast_math][simd]") {
  const std::vector<float> values = FloatsOfUnitInterval();
  const size_t count = values.size();
  test::SimdRows in(1, count), expected(1, count);
  for (size_t i = 0; i < count; ++i) {
    in.values[0][i] = values[i];
    expected.values[0][i] = AcosPoly(values[i]);
  }
  test::CheckEveryTarget(expected, count, [&](float* const* out) {
    HWY_DYNAMIC_DISPATCH(Acos)(in.in.data(), count, out);
  });
}

}  // namespace
}  // namespace ssgi
#endif
