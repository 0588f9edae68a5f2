// Highway twins of the environment's per-pixel reads (core/environment_lighting.h): the same
// operations in the same order as the scalar definitions, so every target gives their bits
// (docs/design.md §11). Lanes are pixels. A per-target header in Highway's "-inl.h" convention.
#if defined(SSGI_CORE_ENVIRONMENT_LIGHTING_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SSGI_CORE_ENVIRONMENT_LIGHTING_INL_H_
#undef SSGI_CORE_ENVIRONMENT_LIGHTING_INL_H_
#else
#define SSGI_CORE_ENVIRONMENT_LIGHTING_INL_H_
#endif

#include "core/environment_lighting.h"
#include "core/math-inl.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// EnvironmentIrradiance(lighting, n) for a non-constant environment: `sh` its nine RGB coefficients.
template <class D>
Vec3V<D> EnvironmentIrradianceV(D d, const std::array<glm::vec3, 9>& sh, const Vec3V<D>& n) {
  const auto c = [&](float k) { return hn::Set(d, k); };
  const hn::Vec<D> y[9] = {c(0.282095f),
                           hn::Mul(c(0.488603f), n.y),
                           hn::Mul(c(0.488603f), n.z),
                           hn::Mul(c(0.488603f), n.x),
                           hn::Mul(hn::Mul(c(1.092548f), n.x), n.y),
                           hn::Mul(hn::Mul(c(1.092548f), n.y), n.z),
                           hn::Mul(c(0.315392f), hn::Sub(hn::Mul(hn::Mul(c(3.0f), n.z), n.z), c(1.0f))),
                           hn::Mul(hn::Mul(c(1.092548f), n.x), n.z),
                           hn::Mul(c(0.546274f), hn::Sub(hn::Mul(n.x, n.x), hn::Mul(n.y, n.y)))};
  Vec3V<D> sum = Scale3(Set3(d, sh[0]), y[0]);
  for (int k = 1; k < 9; ++k) sum = Add3(sum, Scale3(Set3(d, sh[size_t(k)]), y[k]));
  const auto zero = hn::Zero(d);
  return {MaxStd(sum.x, zero), MaxStd(sum.y, zero), MaxStd(sum.z, zero)};
}

// OctahedralEncode(direction).
template <class D>
void OctahedralEncodeV(D d, const Vec3V<D>& direction, hn::Vec<D>& u, hn::Vec<D>& v) {
  const auto zero = hn::Zero(d), one = hn::Set(d, 1.0f), half = hn::Set(d, 0.5f);
  const auto l1 = hn::Add(hn::Add(hn::Abs(direction.x), hn::Abs(direction.y)), hn::Abs(direction.z));
  auto x = hn::Div(direction.x, l1), z = hn::Div(direction.z, l1);
  const auto signX = hn::IfThenElse(hn::Ge(x, zero), one, hn::Neg(one));
  const auto signZ = hn::IfThenElse(hn::Ge(z, zero), one, hn::Neg(one));
  const auto foldedX = hn::Mul(hn::Sub(one, hn::Abs(z)), signX);
  const auto foldedZ = hn::Mul(hn::Sub(one, hn::Abs(x)), signZ);
  const auto below = hn::Lt(direction.y, zero);
  x = hn::IfThenElse(below, foldedX, x);
  z = hn::IfThenElse(below, foldedZ, z);
  u = hn::Add(hn::Mul(x, half), half);
  v = hn::Add(hn::Mul(z, half), half);
}

// SampleLevel (environment_lighting.cpp): bilinear in the bordered level.
template <class D>
Vec3V<D> SampleLevelV(D d, const OctahedralLevel& level, hn::Vec<D> u, hn::Vec<D> v) {
  const hn::RebindToSigned<D> di;
  const auto n = hn::Set(d, float(level.size));
  const auto half = hn::Set(d, 0.5f), one = hn::Set(d, 1.0f);
  const auto x = hn::Add(hn::Mul(u, n), half), y = hn::Add(hn::Mul(v, n), half);
  const auto i = hn::Min(hn::ConvertTo(di, x), hn::Set(di, level.size));
  const auto j = hn::Min(hn::ConvertTo(di, y), hn::Set(di, level.size));
  const auto fx = hn::Sub(x, hn::ConvertTo(d, i)), fy = hn::Sub(y, hn::ConvertTo(d, j));
  const auto stride = hn::Set(di, int32_t(level.texels.c[0].PixelsPerRow()));
  const auto index00 = hn::Add(hn::Mul(j, stride), i);
  const auto index10 = hn::Add(index00, hn::Set(di, 1));
  const auto index01 = hn::Add(index00, stride);
  const auto index11 = hn::Add(index01, hn::Set(di, 1));
  const auto fx1 = hn::Sub(one, fx), fy1 = hn::Sub(one, fy);
  // Neighbouring pixels mostly read neighbouring texels (a smooth surface's reflected directions, a
  // rough level's few texels): when every lane's 2x2 texels lie in one window of a row and the next,
  // two loads per channel serve the four lookups (GatherWindow, core/math-inl.h), else four gathers.
  // The same texels either way.
  const int32_t planeSize = int32_t(level.texels.c[0].PixelsPerRow()) * (level.size + 2);
  const GatherWindow<D> window = WindowFromLowest(d, planeSize - level.texels.c[0].PixelsPerRow(), index00, 1);
  hn::Vec<D> out[3];
  for (int c = 0; c < 3; ++c) {
    const float* t = level.texels.c[c].ConstRow(0);
    hn::Vec<D> t00, t10, t01, t11;
    if (window.holdsAll) {
      const auto placeLeft = hn::IndicesFromVec(d, window.place);
      const auto placeRight = hn::IndicesFromVec(d, hn::Add(window.place, hn::Set(di, 1)));
      const auto upper = hn::LoadU(d, t + window.first);
      const auto lower = hn::LoadU(d, t + window.first + level.texels.c[0].PixelsPerRow());
      t00 = hn::TableLookupLanes(upper, placeLeft);
      t10 = hn::TableLookupLanes(upper, placeRight);
      t01 = hn::TableLookupLanes(lower, placeLeft);
      t11 = hn::TableLookupLanes(lower, placeRight);
    } else {
      t00 = hn::GatherIndex(d, t, index00);
      t10 = hn::GatherIndex(d, t, index10);
      t01 = hn::GatherIndex(d, t, index01);
      t11 = hn::GatherIndex(d, t, index11);
    }
    const auto top = hn::Add(hn::Mul(t00, fx1), hn::Mul(t10, fx));
    const auto bottom = hn::Add(hn::Mul(t01, fx1), hn::Mul(t11, fx));
    out[c] = hn::Add(hn::Mul(top, fy1), hn::Mul(bottom, fy));
  }
  return {out[0], out[1], out[2]};
}

// EnvironmentRadiance(lighting, direction) for a non-constant environment.
template <class D>
Vec3V<D> EnvironmentRadianceV(D d, const EnvironmentLighting& lighting, const Vec3V<D>& direction) {
  hn::Vec<D> u, v;
  OctahedralEncodeV(d, direction, u, v);
  return SampleLevelV(d, lighting.levels[0], u, v);
}

// PrefilteredEnvironment(lighting, direction, roughness) for a non-constant environment.
template <class D>
Vec3V<D> PrefilteredEnvironmentV(D d, const EnvironmentLighting& lighting, const Vec3V<D>& direction,
                                 hn::Vec<D> roughness) {
  const hn::RebindToSigned<D> di;
  const auto position =
      hn::Mul(ClampStd(roughness, hn::Zero(d), hn::Set(d, 1.0f)), hn::Set(d, float(kEnvironmentLevels - 1)));
  const auto lower = hn::Min(hn::ConvertTo(di, position), hn::Set(di, kEnvironmentLevels - 2));
  const auto f = hn::Sub(position, hn::ConvertTo(d, lower));
  hn::Vec<D> u, v;
  OctahedralEncodeV(d, direction, u, v);
  // Each lane's two levels: evaluated for every pair of levels some lane needs, kept where it is
  // that lane's.
  Vec3V<D> a{hn::Zero(d), hn::Zero(d), hn::Zero(d)}, b = a;
  for (int k = 0; k < kEnvironmentLevels - 1; ++k) {
    const auto mine = hn::RebindMask(d, hn::Eq(lower, hn::Set(di, k)));
    if (hn::AllFalse(d, mine)) continue;
    a = IfThenElse3(mine, SampleLevelV(d, lighting.levels[size_t(k)], u, v), a);
    b = IfThenElse3(mine, SampleLevelV(d, lighting.levels[size_t(k) + 1], u, v), b);
  }
  return Add3(Scale3(a, hn::Sub(hn::Set(d, 1.0f), f)), Scale3(b, f));
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#endif  // SSGI_CORE_ENVIRONMENT_LIGHTING_INL_H_
