// The direct light pass on hand-made G-buffers: the GGX / Smith / Schlick BRDF of one light and one
// surface against the formulas evaluated independently here in double precision, the shadowed
// light's visibility, several lights adding up, and the background. The disk light's BRDF against
// the lobe integrated over the disk, as the Embree reference samples it: the highlight's energy, its
// centre and its tails; finite for any unit inputs. The SIMD kernel against the scalar one on every
// target: on random G-buffer rows of every length up to a few vectors, and the whole pass on the
// default scene's buffers at several sizes.
#include "passes/direct_light.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/color.h"
#include "core/lighting.h"
#include "passes/shadow_map.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

using glm::dvec3;

// Radiance toward the viewer of one directional light of zero size on a metallic-roughness surface:
// (Lambert + D V F) n.l E, with GGX D, height-correlated Smith V (Heitz 2014) and Schlick F
// (Filament's formulation, docs/design.md §5). Unit vectors n (normal), v (to viewer), l (to light).
dvec3 AnalyticRadiance(dvec3 albedo, double metallic, double roughness, dvec3 n, dvec3 v, dvec3 l, dvec3 irradiance) {
  const double pi = 3.14159265358979323846;
  const double nl = glm::dot(n, l), nv = glm::dot(n, v);
  if (nl <= 0.0 || nv <= 0.0) return dvec3(0.0);
  const dvec3 h = glm::normalize(v + l);
  const double nh = glm::dot(n, h), vh = glm::dot(v, h);
  const double alpha = std::max(roughness * roughness, 0.045 * 0.045);
  const double a2 = alpha * alpha;
  const double d = a2 / (pi * std::pow(nh * nh * (a2 - 1.0) + 1.0, 2.0));
  const double vis = 0.5 / (nl * std::sqrt(nv * nv * (1.0 - a2) + a2) + nv * std::sqrt(nl * nl * (1.0 - a2) + a2));
  const dvec3 f0 = glm::mix(dvec3(0.04), albedo, metallic);
  const dvec3 f = f0 + (dvec3(1.0) - f0) * std::pow(1.0 - vh, 5.0);
  const dvec3 diffuse = albedo * (1.0 - metallic) / pi;
  return (diffuse + d * vis * f) * nl * irradiance;
}

// A camera at the origin looking down -z: view space is world space.
test::TestScene ViewSpaceScene(int width, int height) {
  CameraDesc camera;
  camera.position = {0.0f, 0.0f, 0.0f};
  camera.target = {0.0f, 0.0f, -1.0f};
  return test::MakeScene(camera, width, height);
}

void SetPixel(GBuffer& g, int x, int y, glm::vec3 albedo, float metallic, glm::vec3 normal, float roughness,
              float depth) {
  g.word[GBufferWord::kAlbedoMetallic].MutableRow(size_t(y))[x] = PackAlbedoMetallic(albedo, metallic);
  g.word[GBufferWord::kNormalRoughness].MutableRow(size_t(y))[x] =
      PackNormalRoughness(glm::normalize(normal), roughness, g.normalEncoding);
  g.word[GBufferWord::kDepth].MutableRow(size_t(y))[x] = PackDepth(depth);
}

glm::vec3 Radiance(const DirectLightOutputs& out, int x, int y) {
  return {out.radiance.c[0].ConstRow(size_t(y))[x], out.radiance.c[1].ConstRow(size_t(y))[x],
          out.radiance.c[2].ConstRow(size_t(y))[x]};
}

TEST_CASE("direct light: one sun on one surface is the analytic GGX value", "[direct_light]") {
  test::TestScene scene = ViewSpaceScene(9, 7);
  const ViewProjection view = MakePerspective(scene.camera, 9, 7);
  const glm::vec3 irradiance(3.0f, 2.5f, 2.0f);
  scene.directionalLights.push_back(test::Sun(glm::normalize(glm::vec3(0.3f, -1.0f, -0.4f)), 0.0f));
  scene.directionalLights[0].irradiance = irradiance;

  struct Surface {
    glm::vec3 albedo, normal;
    float metallic, roughness, depth;
  };
  const Surface surfaces[] = {
      {{0.8f, 0.5f, 0.3f}, {0.0f, 1.0f, 0.3f}, 0.0f, 0.5f, 3.0f},     // rough dielectric
      {{0.95f, 0.64f, 0.54f}, {0.2f, 0.9f, 0.5f}, 1.0f, 0.25f, 2.0f}, // copper
      {{0.9f, 0.9f, 0.9f}, {0.0f, 0.3f, 1.0f}, 1.0f, 0.0f, 5.0f},     // a mirror: alpha clamped
      {{0.5f, 0.5f, 0.5f}, {0.0f, -1.0f, 0.2f}, 0.0f, 0.7f, 4.0f},    // facing away from the light
  };
  for (const Surface& s : surfaces) {
    GBuffer g = MakeGBuffer(9, 7, NormalEncoding::kOct24);
    SetPixel(g, 4, 3, s.albedo, s.metallic, s.normal, s.roughness, s.depth);
    DirectLightOutputs out;
    const DirectLightStats stats = RunDirectLight({g, view, scene}, {}, out);
    CHECK(stats.pixels == 1);
    // What the pass sees: the G-buffer's quantised values.
    const uint32_t w0 = g.word[GBufferWord::kAlbedoMetallic].ConstRow(3)[4],
                   w1 = g.word[GBufferWord::kNormalRoughness].ConstRow(3)[4];
    const ViewProjection::Ray ray = view.PixelRay(4.5f, 3.5f);
    const dvec3 v = glm::normalize(-dvec3(ray.direction));
    const dvec3 expected =
        AnalyticRadiance(dvec3(UnpackAlbedo(w0)), UnpackMetallic(w0), UnpackRoughness(w1),
                         dvec3(UnpackNormal(w1, g.normalEncoding)), v, -dvec3(scene.directionalLights[0].direction),
                         dvec3(irradiance));
    const glm::vec3 got = Radiance(out, 4, 3);
    CAPTURE(s.metallic, s.roughness, got.x, got.y, got.z, expected.x, expected.y, expected.z);
    for (int c = 0; c < 3; ++c) CHECK(double(got[c]) == Approx(expected[c]).epsilon(1e-4).margin(1e-7));
  }
}

TEST_CASE("direct light: a point light is the analytic GGX value under the inverse square in every direction",
          "[direct_light]") {
  // A point light behind, beside and in front of the surface point: no cone cuts it (core/lighting.h),
  // on both kernel paths.
  for (const glm::vec3 position :
       {glm::vec3(0.5f, 2.0f, -1.0f), glm::vec3(-1.5f, 0.5f, -4.5f), glm::vec3(0.2f, 1.0f, -5.5f)}) {
    test::TestScene scene = ViewSpaceScene(9, 7);
    const ViewProjection view = MakePerspective(scene.camera, 9, 7);
    PointLight light;
    light.position = position;
    light.radius = 0.0f;
    light.intensity = glm::vec3(4.0f, 3.0f, 2.0f);
    scene.pointLights.push_back(light);
    GBuffer g = MakeGBuffer(9, 7, NormalEncoding::kOct24);
    SetPixel(g, 4, 3, {0.8f, 0.5f, 0.3f}, 0.0f, {0.0f, 1.0f, 0.3f}, 0.5f, 3.0f);
    const uint32_t w0 = g.word[GBufferWord::kAlbedoMetallic].ConstRow(3)[4],
                   w1 = g.word[GBufferWord::kNormalRoughness].ConstRow(3)[4];
    const ViewProjection::Ray ray = view.PixelRay(4.5f, 3.5f);
    const dvec3 p = dvec3(ray.direction) * double(UnpackDepth(g.word[GBufferWord::kDepth].ConstRow(3)[4]));
    const dvec3 toLight = dvec3(position) - p;
    const double distance2 = glm::dot(toLight, toLight);
    const dvec3 expected = AnalyticRadiance(dvec3(UnpackAlbedo(w0)), UnpackMetallic(w0), UnpackRoughness(w1),
                                            dvec3(UnpackNormal(w1, g.normalEncoding)), glm::normalize(-p),
                                            glm::normalize(toLight), dvec3(light.intensity) / distance2);
    for (const KernelPath kernels : {KernelPath::kScalar, KernelPath::kSimd}) {
      DirectLightOutputs out;
      RunDirectLight({g, view, scene}, {}, out, kernels);
      const glm::vec3 got = Radiance(out, 4, 3);
      CAPTURE(position.x, position.z, int(kernels), got.x, expected.x);
      CHECK(glm::length(dvec3(expected)) > 0.0);
      for (int c = 0; c < 3; ++c) CHECK(double(got[c]) == Approx(expected[c]).epsilon(1e-4).margin(1e-7));
    }
  }
}

TEST_CASE("direct light: lights add up, the shadowed one is scaled by its visibility, background is the "
          "background",
          "[direct_light]") {
  test::TestScene scene = ViewSpaceScene(4, 3);
  const ViewProjection view = MakePerspective(scene.camera, 4, 3);
  scene.directionalLights.push_back(test::Sun(glm::normalize(glm::vec3(0.0f, -1.0f, -0.2f)), 0.0f));
  scene.directionalLights.push_back(test::Sun(glm::normalize(glm::vec3(-0.6f, -1.0f, 0.1f)), 0.0f));
  GBuffer g = MakeGBuffer(4, 3, NormalEncoding::kXyz8);
  for (int x = 0; x < 3; ++x) SetPixel(g, x, 1, {0.6f, 0.6f, 0.6f}, 0.0f, {0.0f, 1.0f, 0.1f}, 0.6f, 2.0f);

  auto only = [&](size_t light) {
    test::TestScene one = scene;
    one.directionalLights = {scene.directionalLights[light]};
    DirectLightOutputs out;
    RunDirectLight({g, view, one}, {}, out);
    return out;
  };
  const DirectLightOutputs first = only(0), second = only(1);
  Plane<float> visibility = MakePlane<float>(4, 3, 1.0f);
  visibility.MutableRow(1)[1] = 0.25f;
  visibility.MutableRow(1)[2] = 0.0f;
  DirectLightInputs in{g, view, scene};
  in.lightVisibility = &visibility;
  in.shadowedLight = 1;
  DirectLightParams params;
  params.background = {0.1f, 0.2f, 0.3f};
  DirectLightOutputs both;
  RunDirectLight(in, params, both);
  const float scale[] = {1.0f, 0.25f, 0.0f};
  for (int x = 0; x < 3; ++x) {
    CAPTURE(x);
    const glm::vec3 expected = Radiance(first, x, 1) + Radiance(second, x, 1) * scale[x];
    const glm::vec3 got = Radiance(both, x, 1);
    for (int c = 0; c < 3; ++c) CHECK(got[c] == Approx(expected[c]).epsilon(1e-6));
  }
  CHECK(Radiance(both, 3, 1) == params.background);
  CHECK(Radiance(both, 0, 0) == params.background);
}

TEST_CASE("direct light: radiance beyond the largest half float is capped there, on every kernel path",
          "[direct_light]") {
  // A sun of 1e36 W/m^2 on a mirror-like surface overflows to +inf in float; a negative one gives
  // negative radiance; a background of 1e30 is out of range too.
  test::TestScene scene = ViewSpaceScene(3, 1);
  const ViewProjection view = MakePerspective(scene.camera, 3, 1);
  test::TestScene negative = scene;
  scene.directionalLights.push_back(test::Sun(glm::normalize(glm::vec3(0.0f, 0.0f, -1.0f)), 0.0f));
  scene.directionalLights.back().irradiance = glm::vec3(1e36f, 1.0f, 0.0f);
  negative.directionalLights.push_back(test::Sun(glm::normalize(glm::vec3(0.0f, 0.0f, -1.0f)), 0.0f));
  negative.directionalLights.back().irradiance = glm::vec3(-5.0f);
  GBuffer g = MakeGBuffer(3, 1, NormalEncoding::kOct24);
  for (int x = 0; x < 2; ++x) SetPixel(g, x, 0, {0.9f, 0.9f, 0.9f}, 1.0f, {0.0f, 0.0f, 1.0f}, 0.0f, 2.0f);
  DirectLightParams params;
  params.background = {1e30f, -1.0f, 0.5f};
  for (KernelPath kernels : {KernelPath::kScalar, KernelPath::kSimd}) {
    DirectLightOutputs out, dark;
    RunDirectLight({g, view, scene}, params, out, kernels);
    RunDirectLight({g, view, negative}, params, dark, kernels);
    CHECK(Radiance(out, 0, 0).x == kMaxRadiance);
    CHECK(Radiance(out, 0, 0).y > 0.0f);
    CHECK(Radiance(out, 0, 0).y < kMaxRadiance);
    CHECK(Radiance(dark, 1, 0) == glm::vec3(0.0f));
    CHECK(Radiance(out, 2, 0) == glm::vec3(kMaxRadiance, 0.0f, 0.5f));
  }
}

// The disk light's tests below: a metal of white base colour, whose Fresnel term is 1 and whose
// diffuse term is 0, so only the GGX lobe is measured; the surface's normal is +z.
constexpr double kPiD = 3.14159265358979323846;
const glm::vec3 kUp(0.0f, 0.0f, 1.0f);

// A unit vector at polar angle theta and azimuth phi about the unit vector w.
glm::vec3 AroundDirection(const glm::dvec3& w, double theta, double phi) {
  const glm::dvec3 helper = std::abs(w.z) < 0.9 ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(1.0, 0.0, 0.0);
  const glm::dvec3 x = glm::normalize(glm::cross(helper, w)), y = glm::cross(w, x);
  return glm::vec3(glm::normalize((x * std::cos(phi) + y * std::sin(phi)) * std::sin(theta) + w * std::cos(theta)));
}

// The integral of f(direction) over the directions within edges.back() of w, by the midpoint rule in
// the polar angle (on `edges`, increasing from 0) and the azimuth (`sectors`), in double.
template <class F>
double IntegrateAround(const glm::dvec3& w, const std::vector<double>& edges, int sectors, F&& f) {
  double sum = 0.0;
  for (size_t i = 0; i + 1 < edges.size(); ++i) {
    const double theta = 0.5 * (edges[i] + edges[i + 1]);
    // The exact solid angle of the ring, shared by its sectors.
    const double ring = 2.0 * kPiD * (std::cos(edges[i]) - std::cos(edges[i + 1])) / sectors;
    for (int j = 0; j < sectors; ++j) sum += ring * f(AroundDirection(w, theta, 2.0 * kPiD * (j + 0.5) / sectors));
  }
  return sum;
}

// Polar angles from 0 to maxTheta: `count` uniform steps, or steps growing geometrically from 1e-5
// (fine on a highlight at the centre, coarse far from it).
std::vector<double> UniformEdges(double maxTheta, int count) {
  std::vector<double> edges;
  for (int i = 0; i <= count; ++i) edges.push_back(maxTheta * i / count);
  return edges;
}
std::vector<double> GeometricEdges(double maxTheta, int count) {
  std::vector<double> edges{0.0};
  for (int i = 0; i < count; ++i) edges.push_back(1e-5 * std::pow(maxTheta / 1e-5, double(i) / (count - 1)));
  return edges;
}

// What the Embree reference computes for a disk light of angular radius atan(t) around l: BrdfCosine
// over the disk's directions over pi sin^2 of its angular radius (its mean over the disk in solid
// angle times 2 / (1 + cos), docs/pipeline.md §Embree reference), per unit of irradiance.
template <class F>
double OverDisk(const glm::dvec3& l, double t, int rings, int sectors, F&& brdfCosine) {
  const double maxTheta = std::atan(t);
  return IntegrateAround(l, UniformEdges(maxTheta, rings), sectors, brdfCosine) /
         (kPiD * std::sin(maxTheta) * std::sin(maxTheta));
}

TEST_CASE("direct light: the sun's highlight keeps the energy of the GGX lobe over the sun's disk", "[direct_light]") {
  // Reflected flux per unit irradiance: the highlight integrated over the view hemisphere (times
  // n.v), against the material's own lobe integrated over the view hemisphere and over the disk, for
  // near-mirrors to rough metals, suns of 0.5, 3 and 10 degrees, from overhead to grazing.
  const SurfaceMaterial metal{glm::vec3(1.0f), 1.0f, 0.0f};
  const std::vector<double> viewEdges = GeometricEdges(kPiD, 300);
  for (const double degrees : {0.5, 3.0, 10.0}) {
    const double t = std::tan(degrees * kPiD / 360.0);
    for (const float roughness : {0.05f, 0.1f, 0.2f, 0.35f, 0.7f}) {
      const float alpha = roughness * roughness;
      for (const double incidence : {0.0, 30.0, 60.0, 75.0}) {
        const double angle = incidence * kPiD / 180.0;
        const glm::dvec3 l(std::sin(angle), 0.0, std::cos(angle));
        // The integral over the view hemisphere, on rings about the light's mirror direction.
        const auto flux = [&](const glm::dvec3& light, auto&& brdfCosine) {
          return IntegrateAround(glm::dvec3(-light.x, -light.y, light.z), viewEdges, 48, [&](const glm::vec3& v) {
            return v.z > 0.0f ? double(brdfCosine(v)) * double(v.z) : 0.0;
          });
        };
        const double highlight = flux(
            l, [&](const glm::vec3& v) { return DiskLightBrdfCosine(metal, alpha, kUp, v, glm::vec3(l), float(t)).x; });
        const double lobe = OverDisk(l, t, 4, 8, [&](const glm::vec3& lSample) {
          return flux(glm::dvec3(lSample),
                      [&](const glm::vec3& v) { return BrdfCosine(metal, alpha, kUp, v, lSample).x; });
        });
        CAPTURE(degrees, roughness, incidence, highlight, lobe);
        CHECK(highlight == Approx(lobe).epsilon(0.02));
      }
    }
  }
}

TEST_CASE("direct light: the sun's highlight is the GGX lobe over the sun's disk at its centre and away from it",
          "[direct_light]") {
  // Widening alpha by the sun's size instead gives 0.5 to 0.8 of it at the centre, and away from it
  // 1.6x (roughness 0.2) to 38x (0.05) too much under a 3 degree sun.
  const SurfaceMaterial metal{glm::vec3(1.0f), 1.0f, 0.0f};
  for (const double degrees : {0.5, 3.0}) {
    const double t = std::tan(degrees * kPiD / 360.0);
    for (const float roughness : {0.05f, 0.2f, 0.35f}) {
      const float alpha = roughness * roughness;
      for (const double incidence : {20.0, 60.0}) {
        const double angle = incidence * kPiD / 180.0;
        const glm::dvec3 l(std::sin(angle), 0.0, std::cos(angle));
        const glm::dvec3 mirror(-l.x, 0.0, l.z);
        // The view turned off the mirror direction in the plane of incidence and across it.
        for (const double offset : {0.0, 10.0, 20.0}) {
          for (const glm::dvec3 axis : {glm::dvec3(0.0, 1.0, 0.0), glm::cross(mirror, glm::dvec3(0.0, 1.0, 0.0))}) {
            const double turn = offset * kPiD / 180.0;
            const glm::vec3 v(mirror * std::cos(turn) + glm::cross(axis, mirror) * std::sin(turn));
            const double exact = OverDisk(l, t, 400, 64, [&](const glm::vec3& lSample) {
              return double(BrdfCosine(metal, alpha, kUp, v, lSample).x);
            });
            const double ours = DiskLightBrdfCosine(metal, alpha, kUp, v, glm::vec3(l), float(t)).x;
            CAPTURE(degrees, roughness, incidence, offset, axis.x, axis.y, axis.z, ours, exact);
            CHECK(ours == Approx(exact).epsilon(offset == 0.0 ? 0.1 : 0.08));
          }
        }
      }
    }
  }
}

TEST_CASE("direct light: the disk light's BRDF is finite and non-negative for any unit inputs", "[direct_light]") {
  // Grazing views and lights down to denormal heights above the surface, zero to denormal to
  // whole-sky light sizes, zero to denormal to the largest alphas, the reflection on the light's
  // centre, and random directions.
  const float heights[] = {1.0f, 0.5f, 1e-3f, 1e-7f, 1e-20f, 1e-38f, 1e-44f, 0.0f, -1e-7f};
  const float sizes[] = {0.0f, 1e-40f, 1e-20f, 1e-7f, 0.0043633f, 0.0261859f, 0.5f, 1.0f};
  const float alphas[] = {0.0f, 1e-40f, 1e-20f, kMinGgxAlpha, 0.3f, 1.0f};
  const float azimuths[] = {0.0f, 0.01f, 1.0f, 3.14159265f};
  const auto above = [](float height, float azimuth) {
    const float across = std::sqrt(std::max(0.0f, 1.0f - height * height));
    return glm::vec3(across * std::cos(azimuth), across * std::sin(azimuth), height);
  };
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  size_t checked = 0;
  const auto check = [&](const glm::vec3& v, const glm::vec3& l) {
    for (const float t : sizes) {
      for (const float alpha : alphas) {
        const SurfaceMaterial material{{unit(rng), unit(rng), unit(rng)}, unit(rng), 0.0f};
        const glm::vec3 value = DiskLightBrdfCosine(material, alpha, kUp, v, l, t);
        for (int c = 0; c < 3; ++c) {
          CAPTURE(v.x, v.y, v.z, l.x, l.y, l.z, t, alpha, value.x, value.y, value.z);
          REQUIRE(std::isfinite(value[c]));
          REQUIRE(value[c] >= 0.0f);
        }
        ++checked;
      }
    }
  };
  for (const float viewHeight : heights) {
    for (const float lightHeight : heights) {
      for (const float azimuth : azimuths) {
        const glm::vec3 v = above(viewHeight, 0.0f);
        check(v, above(lightHeight, azimuth));
        check(v, glm::vec3(-v.x, -v.y, v.z));  // the light's centre on the reflection
      }
    }
  }
  for (int i = 0; i < 20000; ++i) {
    std::normal_distribution<float> normal;
    const glm::vec3 v = glm::normalize(glm::vec3(normal(rng), normal(rng), normal(rng)));
    const glm::vec3 l = glm::normalize(glm::vec3(normal(rng), normal(rng), normal(rng)));
    const SurfaceMaterial material{{unit(rng), unit(rng), unit(rng)}, unit(rng), 0.0f};
    const glm::vec3 value = DiskLightBrdfCosine(material, unit(rng) * unit(rng), kUp, v, l, unit(rng));
    for (int c = 0; c < 3; ++c) REQUIRE(std::isfinite(value[c]));
    ++checked;
  }
  CHECK(checked > 20000);
}

TEST_CASE("direct light: the SIMD kernel equals the scalar kernel on every target", "[direct_light][simd]") {
  constexpr int kWidth = 70;  // a few vectors of every target, and a tail
  Scene scene;
  scene.directionalLights.push_back(test::Sun(test::LightDirection(40.0f, 30.0f), 3.0f));
  scene.directionalLights.push_back(test::Sun(test::LightDirection(70.0f, 200.0f), 0.0f));
  scene.spotLights.push_back(test::Spot({0.5f, 2.5f, 1.0f}, {-0.2f, -1.0f, -0.4f}, 50.0f, 0.1f));
  // A point light with a hard cone edge: the 1e-8 floor of the squared distance, cone scale 1e4.
  scene.spotLights.push_back(test::Spot({-1.0f, 1.0f, 0.5f}, {0.3f, -1.0f, -0.2f}, 35.0f, 0.0f));
  scene.spotLights.back().innerConeDegrees = 35.0f;
  const glm::vec3 background(0.05f, 0.06f, 0.08f);

  std::mt19937 rng(21);
  size_t compared = 0;
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (const ViewProjection& view : test::TwinTestViews(kWidth, 50)) {
    const std::vector<PreparedLight> all = PrepareLights(scene, view.view);
    // One sun, one spot, all four; unshadowed or with one of them shadowed.
    struct Lights {
      std::vector<PreparedLight> lights;
      size_t shadowed;
    };
    const Lights sets[] = {{{all[0]}, 0}, {{all[2]}, 0}, {all, 1}, {all, 3}};
    for (const NormalEncoding encoding : {NormalEncoding::kXyz8, NormalEncoding::kOct24}) {
      for (const size_t y : {size_t(0), size_t(17), size_t(49)}) {
        const test::RandomGBufferRow row(kWidth, rng);
        std::vector<float> visibilities(kWidth);
        for (int x = 0; x < kWidth; ++x) visibilities[x] = x % 5 == 0 ? float(x % 2) : unit(rng);
        for (const Lights& set : sets) {
          const DirectLightContext context{view, set.lights.data(), set.lights.size(), set.shadowed, encoding,
                                           background};
          for (const bool shadowed : {false, true}) {
            const float* visibility = shadowed ? visibilities.data() : nullptr;
            for (int width = 1; width <= kWidth; ++width) {
              std::vector<float> expected(3 * kWidth, -1.0f);
              const size_t expectedShaded = DirectLightRowScalar(
                  context, row.word[GBufferWord::kAlbedoMetallic].data(),
                  row.word[GBufferWord::kNormalRoughness].data(), row.word[GBufferWord::kDepth].data(), visibility, y,
                  width, &expected[0], &expected[kWidth], &expected[2 * kWidth]);
              test::ForEachSimdTarget([&](const char* target) {
                std::vector<float> actual(3 * kWidth, -1.0f);
                const size_t shaded = DirectLightRowSimd(context, row.word[GBufferWord::kAlbedoMetallic].data(),
                                                         row.word[GBufferWord::kNormalRoughness].data(),
                                                         row.word[GBufferWord::kDepth].data(), visibility, y, width,
                                                         &actual[0], &actual[kWidth], &actual[2 * kWidth]);
                CAPTURE(target, view.orthographic, int(encoding), y, set.lights.size(), set.shadowed, shadowed, width);
                CHECK(shaded == expectedShaded);
                // Every pixel the same bits, and nothing written past the row's end.
                const size_t first = test::FirstDifferentBits(actual.data(), expected.data(), actual.size());
                CAPTURE(first);
                REQUIRE(first == actual.size());
                ++compared;
              });
            }
          }
        }
      }
    }
  }
  CHECK(compared >= 2 * 2 * 3 * 4 * 2 * kWidth);
}

// The direct light's inputs in a frame of the default scene: its G-buffer and the filtered
// visibility of its shadowed light.
DirectLightOutputs RunDirectLightOn(const Frame& frame, const test::DefaultScene& scene, KernelPath kernels) {
  DirectLightInputs in{frame.gbuffer.gbuffer, frame.view, scene.scene};
  in.lightVisibility = &frame.shadowVisibility.visibility;
  in.shadowedLight = ShadowCastingLights(scene.scene).front();
  DirectLightOutputs out;
  RunDirectLight(in, scene.config.directLight, out, kernels);
  return out;
}

TEST_CASE("direct light: the SIMD pass gives the scalar pass's bytes on the default scene on every target",
          "[direct_light][simd]") {
  const test::DefaultScene scene = test::LoadDefaultScene();
  for (const auto& [width, height] : {std::pair{1024, 1024}, {1, 1}, {67, 45}, {1023, 769}}) {
    const Frame frame = scene.Render(width, height);
    REQUIRE(frame.shadowMap);
    const DirectLightOutputs scalar = RunDirectLightOn(frame, scene, KernelPath::kScalar);
    const size_t targets = test::ForEachSimdTarget([&](const char* target) {
      const DirectLightOutputs simd = RunDirectLightOn(frame, scene, KernelPath::kSimd);
      for (int c = 0; c < 3; ++c) {
        CAPTURE(target, width, height, c);
        CHECK(test::SameBytes(simd.radiance.c[c], scalar.radiance.c[c]));
      }
    });
    CHECK(targets >= 1);
  }
}

}  // namespace
}  // namespace ssgi
