// Highway twins of the light evaluation (core/lighting.h) for the passes' SIMD kernels: the same
// operations in the same order, so every target gives the scalar bits (docs/design.md §11;
// tests/core/lighting_simd_test.cpp). Lanes are shaded points; the light is the same in every lane.
//
// A per-target header in Highway's "-inl.h" convention: a *_simd.cpp includes it after
// hwy/highway.h, once per target through hwy/foreach_target.h, outside any namespace.
#if defined(SSGI_CORE_LIGHTING_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SSGI_CORE_LIGHTING_INL_H_
#undef SSGI_CORE_LIGHTING_INL_H_
#else
#define SSGI_CORE_LIGHTING_INL_H_
#endif

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

// WidenedAlpha(alpha, tanAngularRadius).
template <class D>
hn::Vec<D> WidenedAlphaV(D d, hn::Vec<D> alpha, hn::Vec<D> tanAngularRadius) {
  return MinStd(hn::Set(d, 1.0f), hn::Add(alpha, hn::Mul(hn::Set(d, 0.5f), tanAngularRadius)));
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#endif  // SSGI_CORE_LIGHTING_INL_H_
