// The Highway twins of the BRDF (core/brdf-inl.h) against the scalar functions, bit for bit, on every
// compiled and supported target: BrdfCosine on random and degenerate geometry (light or viewer
// below the surface, grazing, v = -l) over the range of alphas, and SpecularWeight over and past
// the table's range, its grid points included. Rows of inputs not a multiple of any vector length.
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

// in: n, v, l, albedo (three rows each), metallic, alpha; out: three rows.
void BrdfCosines(const float* const* in, size_t count, float* const* out) {
  const D d;
  for (size_t x = 0; x < count; x += hn::Lanes(d)) {
    const SurfaceMaterialV<D> material{LoadRow3(d, in + 9, x, count), LoadRow(d, in[12], x, count, 0.0f),
                                                 hn::Zero(d)};
    const auto brdf = BrdfCosineV(d, material, LoadRow(d, in[13], x, count, 0.0f), LoadRow3(d, in, x, count),
                                  LoadRow3(d, in + 3, x, count), LoadRow3(d, in + 6, x, count));
    StoreRow3(brdf, d, out, x, count);
  }
}

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
HWY_EXPORT(BrdfCosines);
HWY_EXPORT(SpecularWeights);

namespace {

TEST_CASE("BRDF: BrdfCosineV equals BrdfCosine on every target", "[brdf][simd]") {
  constexpr size_t kCount = 20011;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  test::SimdRows in(14, kCount);
  test::SimdRows expected(3, kCount);
  const float alphas[] = {0.0f, 1e-7f, kMinGgxAlpha, 0.5f, 1.0f};
  for (size_t i = 0; i < kCount; ++i) {
    glm::vec3 n = test::RandomUnitVector(rng), v = test::RandomUnitVector(rng), l = test::RandomUnitVector(rng);
    switch (i % 8) {
      case 0: v = -l; break;                                   // h = 0: falls back to n
      case 1: n = {0.0f, 0.0f, 1.0f}, l = {1.0f, 0.0f, -0.0f}; break;  // grazing light
      case 2: v = l; break;
      default: break;
    }
    const SurfaceMaterial material{{unit(rng), unit(rng), unit(rng)}, i % 3 == 0 ? float(i % 2) : unit(rng), 0.0f};
    const float alpha = i % 4 == 0 ? alphas[(i / 4) % 5] : unit(rng) * unit(rng);
    in.Set3(0, i, n);
    in.Set3(3, i, v);
    in.Set3(6, i, l);
    in.Set3(9, i, material.albedo);
    in.values[12][i] = material.metallic;
    in.values[13][i] = alpha;
    expected.Set3(0, i, BrdfCosine(material, alpha, n, v, l));
  }
  for (size_t count : {size_t(1), size_t(7), size_t(33), kCount})
    test::CheckEveryTarget(expected, count, [&](float* const* out) {
      HWY_DYNAMIC_DISPATCH(BrdfCosines)(in.in.data(), count, out);
    });
}

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
