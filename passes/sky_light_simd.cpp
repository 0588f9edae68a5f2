// The Highway twin of SkyLightRowScalar (sky_light.cpp): the same operations in the same order, so
// every target gives the scalar bits (tests/passes/sky_light_test.cpp checks each compiled target).
// Lanes are pixels of the row; the sky-visibility volume is read by gathers.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/sky_light_simd.cpp"
// clang-format off: foreach_target.h must come first, then highway.h, then the per-target headers.
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
// clang-format on

#include "core/color.h"
#include "core/environment_lighting-inl.h"
#include "core/gbuffer-inl.h"
#include "core/row-inl.h"
#include "passes/sky_light.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// SkyVisibility(volume, position, normal).
template <class D>
hn::Vec<D> SkyVisibilityV(D d, const SkyVisibilityVolume& volume, const Vec3V<D>& position, const Vec3V<D>& normal) {
  const hn::RebindToSigned<D> di;
  const auto offset = hn::Set(d, 0.5f * volume.cellSize);
  const auto inverse = hn::Set(d, volume.inverseCellSize);
  const auto half = hn::Set(d, 0.5f);
  const Vec3V<D> origin = Set3(d, volume.origin);
  const auto q = [&](hn::Vec<D> p, hn::Vec<D> n, hn::Vec<D> o) {
    return hn::Sub(hn::Mul(hn::Sub(hn::Add(p, hn::Mul(n, offset)), o), inverse), half);
  };
  const hn::Vec<D> qs[3] = {q(position.x, normal.x, origin.x), q(position.y, normal.y, origin.y),
                            q(position.z, normal.z, origin.z)};
  const int cells[3] = {volume.cellsX, volume.cellsY, volume.cellsZ};
  hn::Vec<decltype(di)> i0[3], i1[3];
  hn::Vec<D> f[3];
  for (int a = 0; a < 3; ++a) {
    const auto c = ClampStd(qs[a], hn::Zero(d), hn::Set(d, float(cells[a] - 1)));
    i0[a] = hn::ConvertTo(di, c);
    i1[a] = hn::Min(hn::Add(i0[a], hn::Set(di, 1)), hn::Set(di, cells[a] - 1));
    f[a] = hn::Sub(c, hn::ConvertTo(d, i0[a]));
  }
  const auto rowStride = hn::Set(di, volume.cellsX);
  const auto sliceStride = hn::Set(di, volume.cellsX * volume.cellsY);
  const auto base = [&](const hn::Vec<decltype(di)>& x, const hn::Vec<decltype(di)>& y,
                        const hn::Vec<decltype(di)>& z) {
    return hn::ShiftLeft<2>(hn::Add(hn::Add(hn::Mul(z, sliceStride), hn::Mul(y, rowStride)), x));
  };
  const hn::Vec<decltype(di)> corner[8] = {
      base(i0[0], i0[1], i0[2]), base(i1[0], i0[1], i0[2]), base(i0[0], i1[1], i0[2]), base(i1[0], i1[1], i0[2]),
      base(i0[0], i0[1], i1[2]), base(i1[0], i0[1], i1[2]), base(i0[0], i1[1], i1[2]), base(i1[0], i1[1], i1[2])};
  const float* table = volume.coefficients.data();
  const auto one = hn::Set(d, 1.0f);
  // Neighbouring pixels mostly lie in one cell: then every lane reads the same 32 values, loaded
  // once and broadcast instead of gathered. Else they mostly lie in cells side by side along x, whose
  // coefficients are neighbours in the table: a corner whose lanes' four coefficients all lie in one
  // window takes them from one load (GatherWindow, core/math-inl.h). The same values on every path,
  // so the same bits.
  const int32_t firstCorner = hn::GetLane(corner[0]);
  const bool oneCell = hn::AllTrue(di, hn::Eq(corner[0], hn::Set(di, firstCorner))) &&
                       hn::AllTrue(di, hn::Eq(corner[7], hn::Set(di, hn::GetLane(corner[7]))));
  const int32_t tableSize = int32_t(volume.coefficients.size());
  hn::Vec<D> t[4][8];  // coefficient k of corner i
  for (int i = 0; i < 8; ++i) {
    if (oneCell) {
      const int32_t index = hn::GetLane(corner[i]);
      for (int k = 0; k < 4; ++k) t[k][i] = hn::Set(d, table[index + k]);
      continue;
    }
    const GatherWindow<D> window = WindowFromLowest(d, tableSize, corner[i], 3);
    if (window.holdsAll) {
      const auto values = hn::LoadU(d, table + window.first);
      for (int k = 0; k < 4; ++k)
        t[k][i] = hn::TableLookupLanes(values, hn::IndicesFromVec(d, hn::Add(window.place, hn::Set(di, k))));
    } else {
      for (int k = 0; k < 4; ++k) t[k][i] = hn::GatherIndex(d, table, hn::Add(corner[i], hn::Set(di, k)));
    }
  }
  hn::Vec<D> v[4];
  for (int k = 0; k < 4; ++k) {
    const auto lerp = [&](hn::Vec<D> a, hn::Vec<D> b, hn::Vec<D> w) {
      return hn::Add(hn::Mul(a, hn::Sub(one, w)), hn::Mul(b, w));
    };
    const auto x00 = lerp(t[k][0], t[k][1], f[0]), x10 = lerp(t[k][2], t[k][3], f[0]);
    const auto x01 = lerp(t[k][4], t[k][5], f[0]), x11 = lerp(t[k][6], t[k][7], f[0]);
    v[k] = lerp(lerp(x00, x10, f[1]), lerp(x01, x11, f[1]), f[2]);
  }
  const auto sum =
      hn::Add(hn::Add(hn::Add(v[0], hn::Mul(v[1], normal.x)), hn::Mul(v[2], normal.y)), hn::Mul(v[3], normal.z));
  return ClampStd(sum, hn::Zero(d), one);
}

void SkyLightKernel(const SkyLightContext& context, const float* srgbDecode, const SkyLightRow& row, size_t y,
                    int width) {
  const DF d;
  const DU du;
  const glm::mat4& m = context.viewToWorld;
  const Vec3V<DF> m0 = Set3(d, glm::vec3(m[0])), m1 = Set3(d, glm::vec3(m[1])), m2 = Set3(d, glm::vec3(m[2]));
  const Vec3V<DF> m3 = Set3(d, glm::vec3(m[3]));
  const auto rayY = hn::Set(d, context.rays.y[y]);
  const auto one = hn::Set(d, 1.0f);
  const Vec3V<DF> constant = Set3(d, context.environment.constantRadiance);
  for (size_t x = 0; x < size_t(width); x += hn::Lanes(d)) {
    const size_t count = size_t(width);
    const auto depth = UnpackDepthV(d, LoadRow(du, row.word2, x, count, PackDepth(kBackgroundDepth)));
    const auto background = hn::Eq(depth, hn::Set(d, kBackgroundDepth));
    const Vec3V<DF> direct = LoadRow3(d, row.direct, x, count);
    Vec3V<DF> diffuse{hn::Zero(d), hn::Zero(d), hn::Zero(d)};
    auto visibility = one;
    if (!hn::AllTrue(d, background)) {
      const auto word0 = LoadRow(du, row.word0, x, count, 0u);
      const auto word1 = LoadRow(du, row.word1, x, count, 0u);
      const Vec3V<DF> viewNormal = UnpackNormalV(d, word1, context.normalEncoding);
      const Vec3V<DF> normal = Add3(Add3(Scale3(m0, viewNormal.x), Scale3(m1, viewNormal.y)), Scale3(m2, viewNormal.z));
      // Where a lane is background its depth is +inf: what it computes is replaced below.
      const auto safeDepth = hn::IfThenElse(background, one, depth);
      const Vec3V<DF> viewPosition{hn::Mul(LoadRow(d, context.rays.x.data(), x, count, 0.0f), safeDepth),
                                   hn::Mul(rayY, safeDepth), hn::Neg(safeDepth)};
      const Vec3V<DF> position =
          Add3(Add3(Add3(Scale3(m0, viewPosition.x), Scale3(m1, viewPosition.y)), Scale3(m2, viewPosition.z)), m3);
      if (context.visibility) visibility = SkyVisibilityV(d, *context.visibility, position, normal);
      const Vec3V<DF> irradiance =
          context.environment.constant ? constant : EnvironmentIrradianceV(d, context.environment.irradianceSh, normal);
      const auto metallic = UnpackMetallicV(d, word0);
      const Vec3V<DF> albedo = Scale3(UnpackAlbedoV(d, word0, srgbDecode), hn::Sub(one, metallic));
      diffuse = Scale3(Mul3(albedo, irradiance), visibility);
      diffuse = IfThenElse3(background, Vec3V<DF>{hn::Zero(d), hn::Zero(d), hn::Zero(d)}, diffuse);
      visibility = hn::IfThenElse(background, one, visibility);
    }
    Vec3V<DF> lit = Add3(direct, diffuse);
    if (!context.environment.constant && !hn::AllFalse(d, background)) {
      const Vec3V<DF> ray =
          Normalize3(d, Vec3V<DF>{LoadRow(d, context.rays.x.data(), x, count, 0.0f), rayY, hn::Set(d, -1.0f)});
      const Vec3V<DF> direction = Add3(Add3(Scale3(m0, ray.x), Scale3(m1, ray.y)), Scale3(m2, ray.z));
      lit = IfThenElse3(background, EnvironmentRadianceV(d, context.environment, direction), lit);
    }
    StoreRow3(diffuse, d, row.diffuse, x, count);
    StoreRow(visibility, d, row.visibility, x, count);
    StoreRow3(lit, d, row.lit, x, count);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(SkyLightKernel);

void SkyLightRowSimd(const SkyLightContext& context, const SkyLightRow& row, size_t y, int width) {
  HWY_DYNAMIC_DISPATCH(SkyLightKernel)(context, SrgbDecodeTableForKernels(), row, y, width);
}

}  // namespace ssgi
#endif
