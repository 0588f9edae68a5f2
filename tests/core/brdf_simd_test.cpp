// The Highway twins of the BRDF (core/brdf-inl.h) against the scalar functions, bit for bit, on every
// compiled and supported target: SpecularWeight over and past the table's range, its grid points
// included, on rows of inputs not a multiple of any vector length. The GGX, Smith and Fresnel terms
// are checked through the disk light's BRDF (tests/core/lighting_simd_test.cpp).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tests/core/brdf_simd_test.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "core/brdf-inl.h"
#include "core/row-inl.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<float>;

// in: f0 (three rows), n.v, roughness; out: three rows.
void SpecularWeights(const float* const* in, size_t count, float* const* out) {
  const D d;
  const float* table = DfgTableForKernels();
  for (size_t x = 0; x < count; x += hn::Lanes(d)) {
    const auto weight = SpecularWeightV(d, LoadRow3(d, in, x, count), LoadRow(d, in[3], x, count, 0.0f),
                                        LoadRow(d, in[4], x, count, 0.0f), table);
    StoreRow3(weight, d, out, x, count);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <catch2/catch.hpp>

#include "tests/simd_rows.h"

namespace ssgi {
HWY_EXPORT(SpecularWeights);

namespace {

TEST_CASE("BRDF: SpecularWeightV equals SpecularWeight on every target", "[brdf][simd]") {
  constexpr size_t kCount = 40009;
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), wide(-0.2f, 1.2f);
  test::SimdRows in(5, kCount);
  test::SimdRows expected(3, kCount);
  for (size_t i = 0; i < kCount; ++i) {
    const glm::vec3 f0(unit(rng), unit(rng), unit(rng));
    // Every grid point of the table and every roughness code; then runs of 16 pixels of one
    // roughness with n.v rising or falling by steps from 1/2000 to 1/31 (as across a surface,
    // where the kernel reads the table from a window when the run's entries fit one, to the table's
    // edges and past them); then anywhere around [0, 1].
    float nDotV = i < 1024 ? float(i % kDfgSize) / (kDfgSize - 1) : wide(rng);
    float roughness = i < 1024 ? float(i / kDfgSize) / (kDfgSize - 1)
                      : i < 2048 ? float(i % 256) / 255.0f
                                 : wide(rng);
    if (i >= 2048 && i < 2048 + 16 * 1024) {
      const size_t run = (i - 2048) / 16, lane = (i - 2048) % 16;
      const float step = (run % 2 == 0 ? 1.0f : -1.0f) * (1.0f + float(run / 2 % 64)) / 2000.0f;
      nDotV = -0.05f + 1.1f * float(run % 97) / 96.0f + float(lane) * step;
      roughness = float(run / 2 % 34) / 32.0f - 0.03f;
    }
    in.Set3(0, i, f0);
    in.values[3][i] = i == 1024 ? -0.0f : nDotV;
    in.values[4][i] = roughness;
    expected.Set3(0, i, SpecularWeight(f0, in.values[3][i], roughness));
  }
  for (size_t count : {size_t(1), size_t(15), size_t(40), kCount})
    test::CheckEveryTarget(expected, count, [&](float* const* out) {
      HWY_DYNAMIC_DISPATCH(SpecularWeights)(in.in.data(), count, out);
    });
}

}  // namespace
}  // namespace ssgi
#endif
