// The Highway twins of the light evaluation (core/lighting-inl.h) against the scalar functions, bit
// for bit, on every compiled and supported target: a directional light and spot lights of several
// sizes and cones at random points, points inside the emitter and at its centre; WidenedAlpha.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tests/core/lighting_simd_test.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "core/lighting-inl.h"
#include "core/row-inl.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<float>;

// in: point (three rows), alpha; out: toLight, irradiance (three rows each), tanAngularRadius,
// WidenedAlpha(alpha, tanAngularRadius).
void EvaluateLights(const PreparedLight& light, const float* const* in, size_t count, float* const* out) {
  const D d;
  for (size_t x = 0; x < count; x += hn::Lanes(d)) {
    const LightAtPointV<D> l = EvaluateV(d, light, LoadRow3(d, in, x, count));
    StoreRow3(l.toLight, d, out, x, count);
    StoreRow3(l.irradiance, d, out + 3, x, count);
    StoreRow(l.tanAngularRadius, d, out[6], x, count);
    StoreRow(WidenedAlphaV(d, LoadRow(d, in[3], x, count, 0.0f), l.tanAngularRadius), d, out[7], x, count);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "tests/simd_rows.h"

namespace ssgi {
HWY_EXPORT(EvaluateLights);

namespace {

TEST_CASE("lights: EvaluateV and WidenedAlphaV equal Evaluate and WidenedAlpha on every target",
          "[lighting][simd]") {
  const glm::mat4 view = glm::mat4(1.0f);
  std::vector<PreparedLight> lights;
  DirectionalLight sun;
  sun.direction = glm::normalize(glm::vec3(-0.55f, -1.0f, -0.4f));
  sun.angularDiameterDegrees = 3.0f;
  lights.push_back(Prepare(sun, view));
  SpotLight spot;
  spot.position = {0.5f, 2.5f, 1.0f};
  spot.direction = glm::normalize(glm::vec3(-0.2f, -1.0f, -0.4f));
  spot.intensity = {20.0f, 18.0f, 15.0f};
  spot.radius = 0.1f;
  spot.innerConeDegrees = 20.0f;
  spot.outerConeDegrees = 50.0f;
  lights.push_back(Prepare(spot, view));
  spot.radius = 0.0f;  // a point: the 1e-8 floor on the squared distance
  spot.innerConeDegrees = spot.outerConeDegrees;  // a hard cone edge
  lights.push_back(Prepare(spot, view));

  constexpr size_t kCount = 10007;
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> box(-3.0f, 3.0f), unit(0.0f, 1.0f);
  for (const PreparedLight& light : lights) {
    test::SimdRows in(4, kCount), expected(8, kCount);
    for (size_t i = 0; i < kCount; ++i) {
      glm::vec3 point(box(rng), box(rng), box(rng));
      if (i % 50 == 0) point = light.position;  // at the emitter's centre
      if (i % 50 == 1) point = light.position + 0.5f * light.radius * test::RandomUnitVector(rng);  // inside it
      const float alpha = i % 7 == 0 ? 1.0f : unit(rng);
      in.Set3(0, i, point);
      in.values[3][i] = alpha;
      const LightAtPoint l = Evaluate(light, point);
      expected.Set3(0, i, l.toLight);
      expected.Set3(3, i, l.irradiance);
      expected.values[6][i] = l.tanAngularRadius;
      expected.values[7][i] = WidenedAlpha(alpha, l.tanAngularRadius);
    }
    CAPTURE(light.isSpot, light.radius);
    for (size_t count : {size_t(1), size_t(9), size_t(31), kCount})
      test::CheckEveryTarget(expected, count, [&](float* const* out) {
        HWY_DYNAMIC_DISPATCH(EvaluateLights)(light, in.in.data(), count, out);
      });
  }
}

}  // namespace
}  // namespace ssgi
#endif
