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

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#endif  // SSGI_CORE_ENVIRONMENT_LIGHTING_INL_H_
