// The Highway twins of LinearToSrgbCode and UnormCode8 (core/color-inl.h) against the scalar
// encoders, on every compiled and supported target: values across every exponent from 0 past 1 (and
// each code boundary's neighbours), negatives, infinities and NaN. The sweep's vectors fall into
// nearby buckets (BucketCodeV's in-register window) and the boundaries' neighbours, listed code by
// code, far apart (its gather).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tests/core/color_simd_test.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "core/color-inl.h"
#include "core/row-inl.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// in: values; out: their sRGB codes and unorm codes, as floats.
void EncodeValues(const float* const* in, size_t count, float* const* out) {
  const DF df;
  const CodeBuckets& encode = SrgbEncodeBuckets();
  for (size_t i = 0; i < count; i += hn::Lanes(df)) {
    const VF value = LoadRow(df, in[0], i, count, 0.0f);
    StoreRow(hn::ConvertTo(df, LinearToSrgbCodeV(value, encode)), df, out[0], i, count);
    StoreRow(hn::ConvertTo(df, UnormCode8V(value)), df, out[1], i, count);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "tests/simd_rows.h"

namespace ssgi {
HWY_EXPORT(EncodeValues);

namespace {

TEST_CASE("color: the 8-bit encoders' twins give the scalar codes on every target", "[color][simd]") {
  std::vector<float> values;
  // Every 61st float from +0 to 2 (all exponents of [0, 2), a few million values).
  for (uint32_t bits = 0; bits <= std::bit_cast<uint32_t>(2.0f); bits += 61) values.push_back(std::bit_cast<float>(bits));
  // The neighbours of each code's boundaries, for both encoders, and of each sRGB code's value.
  for (int code = 0; code < 256; ++code) {
    const float half = (float(code) + 0.5f) / 255.0f;
    for (const float boundary : {SrgbToLinear(half), half, SrgbCodeToLinear(uint8_t(code))}) {
      float below = boundary, above = boundary;
      for (int step = 0; step < 3; ++step) {
        below = std::nextafter(below, 0.0f);
        above = std::nextafter(above, 2.0f);
        values.push_back(below);
        values.push_back(above);
      }
    }
  }
  const float infinity = std::numeric_limits<float>::infinity();
  for (const float special : {-0.0f, -1e-30f, -0.5f, -infinity, infinity, std::numeric_limits<float>::quiet_NaN(),
                              1.0f, 255.0f, 1e30f, std::numeric_limits<float>::denorm_min()})
    values.push_back(special);
  const size_t count = values.size();
  test::SimdRows in(1, count), expected(2, count);
  for (size_t i = 0; i < count; ++i) {
    in.values[0][i] = values[i];
    expected.values[0][i] = float(LinearToSrgbCode(values[i]));
    expected.values[1][i] = float(UnormCode8(values[i]));
  }
  test::CheckEveryTarget(expected, count, [&](float* const* out) {
    HWY_DYNAMIC_DISPATCH(EncodeValues)(in.in.data(), count, out);
  });
}

}  // namespace
}  // namespace ssgi
#endif
