// The Highway twins of the light evaluation (core/lighting-inl.h) against the scalar functions, bit
// for bit, on every compiled and supported target: a directional light and spot lights of several
// sizes and cones at random points, points inside the emitter and at its centre; the disk light's
// BRDF and its representative direction on random and degenerate geometry (the reflection on the
// centre, opposite it, on the disk's rim, grazing views and lights down to denormal heights, below
// the surface) over the range of alphas and light sizes, zero and denormal ones included.
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

// in: point (three rows); out: toLight, irradiance (three rows each), tanAngularRadius.
void EvaluateLights(const PreparedLight& light, const float* const* in, size_t count, float* const* out) {
  const D d;
  for (size_t x = 0; x < count; x += hn::Lanes(d)) {
    const LightAtPointV<D> l = EvaluateV(d, light, LoadRow3(d, in, x, count));
    StoreRow3(l.toLight, d, out, x, count);
    StoreRow3(l.irradiance, d, out + 3, x, count);
    StoreRow(l.tanAngularRadius, d, out[6], x, count);
  }
}

// in: n, v, l, albedo (three rows each), metallic, alpha, tanAngularRadius; out:
// DiskLightBrdfCosine, RepresentativeDirection(reflect(-v, n), l, tanAngularRadius) (three rows each).
void DiskLightBrdfCosines(const float* const* in, size_t count, float* const* out) {
  const D d;
  for (size_t x = 0; x < count; x += hn::Lanes(d)) {
    const Vec3V<D> n = LoadRow3(d, in, x, count), v = LoadRow3(d, in + 3, x, count), l = LoadRow3(d, in + 6, x, count);
    const SurfaceMaterialV<D> material{LoadRow3(d, in + 9, x, count), LoadRow(d, in[12], x, count, 0.0f), hn::Zero(d)};
    const auto alpha = LoadRow(d, in[13], x, count, 0.0f);
    const auto tanAngularRadius = LoadRow(d, in[14], x, count, 0.0f);
    StoreRow3(DiskLightBrdfCosineV(d, material, alpha, n, v, l, tanAngularRadius), d, out, x, count);
    const Vec3V<D> r = Sub3(Scale3(n, hn::Mul(hn::Set(d, 2.0f), Dot3(n, v))), v);
    StoreRow3(RepresentativeDirectionV(d, r, l, tanAngularRadius), d, out + 3, x, count);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <cmath>

#include "tests/simd_rows.h"

namespace ssgi {
HWY_EXPORT(EvaluateLights);
HWY_EXPORT(DiskLightBrdfCosines);

namespace {

TEST_CASE("lights: EvaluateV equals Evaluate on every target", "[lighting][simd]") {
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
    test::SimdRows in(3, kCount), expected(7, kCount);
    for (size_t i = 0; i < kCount; ++i) {
      glm::vec3 point(box(rng), box(rng), box(rng));
      if (i % 50 == 0) point = light.position;  // at the emitter's centre
      if (i % 50 == 1) point = light.position + 0.5f * light.radius * test::RandomUnitVector(rng);  // inside it
      in.Set3(0, i, point);
      const LightAtPoint l = Evaluate(light, point);
      expected.Set3(0, i, l.toLight);
      expected.Set3(3, i, l.irradiance);
      expected.values[6][i] = l.tanAngularRadius;
    }
    CAPTURE(light.isSpot, light.radius);
    for (size_t count : {size_t(1), size_t(9), size_t(31), kCount})
      test::CheckEveryTarget(expected, count, [&](float* const* out) {
        HWY_DYNAMIC_DISPATCH(EvaluateLights)(light, in.in.data(), count, out);
      });
  }
}

TEST_CASE("lights: DiskLightBrdfCosineV and RepresentativeDirectionV equal the scalar functions on every target",
          "[lighting][simd]") {
  constexpr size_t kCount = 20011;
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  test::SimdRows in(15, kCount), expected(6, kCount);
  const float alphas[] = {0.0f, 1e-30f, 1e-7f, kMinGgxAlpha, 0.04f, 0.5f, 1.0f};
  // Zero, denormal and tiny sizes, the suns of 0.5, 3 and 10 degrees, spots near and inside.
  const float sizes[] = {0.0f, 1e-40f, 1e-7f, 0.0043633f, 0.0261859f, 0.0874887f, 0.5f, 1.0f};
  // How far a grazing direction is above the surface: down to denormals, and 0.
  const float heights[] = {0.0f, 1e-44f, 1e-38f, 1e-20f, 1e-7f, 1e-3f};
  // A unit vector `height` above the surface of normal n (about: normalize rounds).
  const auto grazing = [&](const glm::vec3& n, float height) {
    const glm::vec3 w = test::RandomUnitVector(rng);
    return glm::normalize(glm::normalize(w - n * glm::dot(n, w)) + n * height);
  };
  for (size_t i = 0; i < kCount; ++i) {
    glm::vec3 n = test::RandomUnitVector(rng), v = test::RandomUnitVector(rng), l = test::RandomUnitVector(rng);
    float t = i % 3 == 0 ? sizes[(i / 3) % 8] : unit(rng) * unit(rng);
    const glm::vec3 r = n * (2.0f * glm::dot(n, v)) - v;
    switch (i % 13) {
      case 0:
        l = r;
        break;  // the reflection on the centre
      case 1:
        l = -r;
        break;  // opposite it
      case 2:
        l = glm::normalize(r + 0.3f * test::RandomUnitVector(rng));
        break;   // near it
      case 3: {  // on the disk's rim, where the two definitions meet, and just inside and outside
        const glm::vec3 across = glm::normalize(glm::cross(r, test::RandomUnitVector(rng)));
        t = 0.05f + 0.1f * unit(rng);
        l = glm::normalize(r - across * (t * (1.0f + (float(i % 3) - 1.0f) * 1e-6f)));
        break;
      }
      case 4:
        v = n;
        break;  // r = n
      case 5:
        n = {0.0f, 0.0f, 1.0f}, l = {1.0f, 0.0f, -0.0f};
        break;  // grazing light
      case 6:
        v = -l;
        break;
      case 7:
        v = grazing(n, heights[(i / 13) % 6]);
        break;  // grazing views: the slope radius grows without bound
      case 8:
        l = grazing(n, heights[(i / 13) % 6]);
        break;
      case 9:
        v = grazing(n, heights[(i / 13) % 6]), l = glm::normalize(n * (2.0f * glm::dot(n, v)) - v);
        break;
      default:
        break;
    }
    const SurfaceMaterial material{{unit(rng), unit(rng), unit(rng)}, i % 4 == 0 ? float(i % 2) : unit(rng), 0.0f};
    const float alpha = i % 5 == 0 ? alphas[(i / 5) % 6] : unit(rng) * unit(rng);
    in.Set3(0, i, n);
    in.Set3(3, i, v);
    in.Set3(6, i, l);
    in.Set3(9, i, material.albedo);
    in.values[12][i] = material.metallic;
    in.values[13][i] = alpha;
    in.values[14][i] = t;
    expected.Set3(0, i, DiskLightBrdfCosine(material, alpha, n, v, l, t));
    expected.Set3(3, i, RepresentativeDirection(n * (2.0f * glm::dot(n, v)) - v, l, t));
    // Finite for any unit inputs, the degenerate ones included.
    for (int c = 0; c < 6; ++c) REQUIRE(std::isfinite(expected.values[size_t(c)][i]));
  }
  for (size_t count : {size_t(1), size_t(7), size_t(33), kCount})
    test::CheckEveryTarget(expected, count, [&](float* const* out) {
      HWY_DYNAMIC_DISPATCH(DiskLightBrdfCosines)(in.in.data(), count, out);
    });
}

}  // namespace
}  // namespace ssgi
#endif
