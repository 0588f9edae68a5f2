// The Highway twin of SampleTexture (core/texture-inl.h) against the scalar sampler, bit for bit, on
// every compiled and supported target: textures of odd, even, strip and 1x1 sizes in both encodings,
// lookups anywhere (UVs far outside [0, 1], on texel edges, non-finite) with footprints from none
// to past the whole texture (every mip level, blends between them, NaN and infinity), and runs of
// lookups as a row of pixels makes them.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tests/core/texture_simd_test.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "core/row-inl.h"
#include "core/texture-inl.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// in: u, v, footprint; out: r, g, b, a.
void SampleTextures(const TextureView& view, const float* const* in, size_t count, float* const* out) {
  const DF df;
  for (size_t i = 0; i < count; i += hn::Lanes(df)) {
    const Vec3V<DF> lookup = LoadRow3(df, in, i, count);
    const Vec4V texel = SampleTextureV(view, lookup.x, lookup.y, lookup.z);
    StoreRow3(Vec3V<DF>{texel.r, texel.g, texel.b}, df, out, i, count);
    StoreRow(texel.a, df, out[3], i, count);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <cmath>
#include <limits>

#include "tests/simd_rows.h"

namespace ssgi {
HWY_EXPORT(SampleTextures);

namespace {

TEST_CASE("texture: SampleTextureV equals SampleTexture on every target", "[texture][simd]") {
  std::mt19937 rng(21);
  for (const auto& [width, height] : {std::pair{37, 23}, std::pair{64, 64}, std::pair{1, 9}, std::pair{1, 1}}) {
    std::vector<uint8_t> rgba(size_t(width) * size_t(height) * 4);
    for (uint8_t& texel : rgba) texel = uint8_t(rng());
    // Both encodings, and the three wrap modes (repeat by the sRGB texture, clamp and mirror mixed
    // across the axes by the linear one, and the reverse).
    for (const auto& [encoding, wrapU, wrapV] :
         {std::tuple{TextureEncoding::kSrgb, TextureWrap::kRepeat, TextureWrap::kRepeat},
          std::tuple{TextureEncoding::kLinear, TextureWrap::kRepeat, TextureWrap::kRepeat},
          std::tuple{TextureEncoding::kLinear, TextureWrap::kClamp, TextureWrap::kMirror},
          std::tuple{TextureEncoding::kSrgb, TextureWrap::kMirror, TextureWrap::kClamp}}) {
      Texture texture = MakeTexture(width, height, rgba, encoding);
      texture.wrapU = wrapU;
      texture.wrapV = wrapV;
      const TextureView view = ViewOf(texture);
      constexpr size_t kCount = 4000;
      test::SimdRows in(3, kCount), expected(4, kCount);
      std::uniform_real_distribution<float> uv(-3.0f, 4.0f), unit(0.0f, 1.0f);
      const float infinity = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
      for (size_t i = 0; i < kCount; ++i) {
        float u = uv(rng), v = uv(rng);
        if (i % 7 == 0) u = float(rng() % size_t(width + 1)) / float(width);  // on a texel edge
        if (i % 11 == 0) v = float(rng() % size_t(height + 1)) / float(height);
        if (i % 97 == 0) u = (i % 2 == 0) ? nan : infinity;
        // Footprints of 2^-12 to 2^2 texture widths (log-uniform), and the special ones.
        float footprint = std::exp2(-12.0f + 14.0f * unit(rng));
        if (i % 13 == 0) footprint = 0.0f;
        if (i % 17 == 0) footprint = nan;
        if (i % 19 == 0) footprint = infinity;
        if (i % 23 == 0) footprint = 1.0f / float(std::max(width, height));  // exactly level 0's texel
        in.values[0][i] = u;
        in.values[1][i] = v;
        in.values[2][i] = footprint;
        const glm::vec4 texel = SampleTexture(texture, {u, v}, footprint);
        for (int c = 0; c < 4; ++c) expected.values[size_t(c)][i] = texel[c];
      }
      CAPTURE(width, height, int(encoding), int(wrapU), int(wrapV));
      test::CheckEveryTarget(expected, kCount, [&](float* const* out) {
        HWY_DYNAMIC_DISPATCH(SampleTextures)(view, in.in.data(), kCount, out);
      });
    }
  }
}

// Lookups as a row of pixels makes them: runs of UVs a fraction of a texel apart, one footprint per
// run, so that a vector's bilinear pairs are mostly neighbours in memory (read by the paired
// gathers) and sometimes wrap at the texture's right edge (read one texel at a time).
TEST_CASE("texture: SampleTextureV equals SampleTexture on every target, coherent rows", "[texture][simd]") {
  std::mt19937 rng(22);
  for (const auto& [width, height] : {std::pair{37, 23}, std::pair{256, 64}, std::pair{2, 5}}) {
    std::vector<uint8_t> rgba(size_t(width) * size_t(height) * 4);
    for (uint8_t& texel : rgba) texel = uint8_t(rng());
    const Texture texture = MakeTexture(width, height, rgba, TextureEncoding::kSrgb);
    const TextureView view = ViewOf(texture);
    constexpr size_t kRun = 64, kCount = 64 * kRun;
    test::SimdRows in(3, kCount), expected(4, kCount);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (size_t run = 0; run < kCount / kRun; ++run) {
      // From level 0 magnified to a few levels down, and a start anywhere (some runs cross u = 1).
      const float footprint = std::exp2(-2.0f - 10.0f * unit(rng));
      const float step = footprint * (0.25f + unit(rng));
      float u = 4.0f * unit(rng) - 1.0f;
      const float v = unit(rng), vStep = 0.1f * step * unit(rng);
      for (size_t i = run * kRun; i < (run + 1) * kRun; ++i, u += step) {
        in.values[0][i] = u;
        in.values[1][i] = v + vStep * float(i - run * kRun);
        in.values[2][i] = footprint;
        const glm::vec4 texel = SampleTexture(texture, {u, in.values[1][i]}, footprint);
        for (int c = 0; c < 4; ++c) expected.values[size_t(c)][i] = texel[c];
      }
    }
    CAPTURE(width, height);
    test::CheckEveryTarget(expected, kCount, [&](float* const* out) {
      HWY_DYNAMIC_DISPATCH(SampleTextures)(view, in.in.data(), kCount, out);
    });
  }
}

}  // namespace
}  // namespace ssgi
#endif
