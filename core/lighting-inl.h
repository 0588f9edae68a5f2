// Highway twins of the light evaluation and the disk light's BRDF (core/lighting.h) for the passes'
// SIMD kernels: the same operations in the same order, so every target gives the scalar bits
// (docs/design.md §11; tests/core/lighting_simd_test.cpp). Lanes are shaded points; the light is the
// same in every lane.
//
// A per-target header in Highway's "-inl.h" convention: a *_simd.cpp includes it after
// hwy/highway.h, once per target through hwy/foreach_target.h, outside any namespace.
#if defined(SSGI_CORE_LIGHTING_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SSGI_CORE_LIGHTING_INL_H_
#undef SSGI_CORE_LIGHTING_INL_H_
#else
#define SSGI_CORE_LIGHTING_INL_H_
#endif

#include "core/brdf-inl.h"
#include "core/lighting.h"
#include "core/math-inl.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

template <class D>
struct LightAtPointV {
  Vec3V<D> toLight;
  Vec3V<D> irradiance;
  hn::Vec<D> tanAngularRadius;
};

// Evaluate(light, point).
template <class D>
LightAtPointV<D> EvaluateV(D d, const PreparedLight& light, const Vec3V<D>& point) {
  const Vec3V<D> awayFromLight = Set3(d, -light.direction);
  if (!light.isSpot) return {awayFromLight, Set3(d, light.power), hn::Set(d, light.tanAngularRadius)};
  const auto zero = hn::Zero(d);
  const auto one = hn::Set(d, 1.0f);
  const Vec3V<D> offset = Sub3(Set3(d, light.position), point);
  const auto distance2 = Dot3(offset, offset);
  const auto distance = hn::Sqrt(distance2);
  LightAtPointV<D> out;
  out.toLight = IfThenElse3(hn::Gt(distance, zero), Div3(offset, distance), awayFromLight);
  const auto cosAxis = Dot3(Neg3(out.toLight), Set3(d, light.direction));
  const auto cone =
      ClampStd(hn::Mul(hn::Sub(cosAxis, hn::Set(d, light.cosOuter)), hn::Set(d, light.coneScale)), zero, one);
  const auto nearest = hn::Set(d, std::max(light.radius * light.radius, 1e-8f));
  out.irradiance = Scale3(Set3(d, light.power), hn::Div(hn::Mul(cone, cone), MaxStd(distance2, nearest)));
  const auto radius = hn::Set(d, light.radius);
  out.tanAngularRadius = hn::IfThenElse(hn::Gt(distance, radius), hn::Div(radius, distance), one);
  return out;
}

// RepresentativeDirection(r, l, radius): every lane computes the remapped direction, and the lanes
// whose scalar definition returns early take l or r.
template <class D>
Vec3V<D> RepresentativeDirectionV(D d, const Vec3V<D>& r, const Vec3V<D>& l, hn::Vec<D> radius) {
  const auto zero = hn::Zero(d);
  const auto rDotL = Dot3(r, l);
  const auto centre = hn::Not(hn::And(hn::Gt(rDotL, zero), hn::Gt(radius, zero)));
  const Vec3V<D> s = Sub3(r, Scale3(l, rDotL));
  const auto sLength = hn::Sqrt(Dot3(s, s));
  const auto u = hn::Mul(radius, rDotL);
  const auto root = hn::Sqrt(hn::Sub(hn::Mul(sLength, sLength), hn::Mul(u, u)));
  const auto k = hn::Div(hn::Mul(radius, u), hn::Mul(sLength, hn::Add(sLength, root)));
  const Vec3V<D> remapped = Normalize3(d, Add3(l, Scale3(s, k)));
  return IfThenElse3(centre, l, IfThenElse3(hn::Le(sLength, u), r, remapped));
}

// DiskLightBrdfCosine(m, alpha, n, v, l, tanAngularRadius): every lane computes the specular term,
// and the lanes whose scalar definition skips it or returns early take 0.
template <class D>
Vec3V<D> DiskLightBrdfCosineV(D d, const SurfaceMaterialV<D>& m, hn::Vec<D> alpha, const Vec3V<D>& n, const Vec3V<D>& v,
                              const Vec3V<D>& l, hn::Vec<D> tanAngularRadius) {
  const auto zero = hn::Zero(d);
  const auto one = hn::Set(d, 1.0f);
  const auto nDotL = Dot3(n, l);
  const auto nDotV = Dot3(n, v);
  const auto lit = hn::And(hn::Gt(nDotL, zero), hn::Gt(nDotV, zero));
  const Vec3V<D> diffuse = Scale3(m.albedo, hn::Div(hn::Sub(one, m.metallic), hn::Set(d, kPi)));
  const auto a = MaxStd(alpha, hn::Set(d, kMinGgxAlpha));
  const auto slopeRadius = hn::Div(hn::Mul(hn::Set(d, 0.5f), tanAngularRadius), hn::Sqrt(nDotV));
  const auto peakAlpha = MinStd(one, hn::Sqrt(hn::Add(hn::Mul(a, a), hn::Mul(slopeRadius, slopeRadius))));
  const Vec3V<D> r = Sub3(Scale3(n, hn::Mul(hn::Set(d, 2.0f), nDotV)), v);
  const Vec3V<D> toDisk =
      RepresentativeDirectionV(d, r, l, hn::Div(hn::Mul(tanAngularRadius, slopeRadius), hn::Add(a, peakAlpha)));
  const auto nDotDisk = Dot3(n, toDisk);
  Vec3V<D> h = Add3(v, toDisk);
  const auto hLength = Length3(h);
  h = IfThenElse3(hn::Gt(hLength, zero), Div3(h, hLength), n);
  const auto nDotH = ClampStd(Dot3(n, h), zero, one);
  const auto vDotH = ClampStd(Dot3(v, h), zero, one);
  const auto peak = hn::Div(one, hn::Mul(hn::Set(d, kPi), hn::Mul(peakAlpha, peakAlpha)));
  const auto distribution = MinStd(GgxDistributionV(d, nDotH, a), peak);
  const Vec3V<D> specular = Scale3(SchlickFresnelV(d, vDotH, SpecularF0V(d, m)),
                                   hn::Mul(distribution, SmithGgxCorrelatedVisibilityCosineV(d, nDotV, nDotDisk, a)));
  const auto reflects = hn::Gt(nDotDisk, zero);
  const Vec3V<D> cosine =
      Add3(Scale3(diffuse, nDotL), {hn::IfThenElseZero(reflects, specular.x), hn::IfThenElseZero(reflects, specular.y),
                                    hn::IfThenElseZero(reflects, specular.z)});
  return {hn::IfThenElseZero(lit, cosine.x), hn::IfThenElseZero(lit, cosine.y), hn::IfThenElseZero(lit, cosine.z)};
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#endif  // SSGI_CORE_LIGHTING_INL_H_
