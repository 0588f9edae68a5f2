// The direct light pass on hand-made G-buffers: the GGX / Smith / Schlick BRDF of one light and one
// surface against the formulas evaluated independently here in double precision, the shadowed
// light's visibility, several lights adding up, and the background. The SIMD kernel against the
// scalar one on every target: on random G-buffer rows of every length up to a few vectors, and the
// whole pass on the default scene's buffers at several sizes.
#include "passes/direct_light.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "core/color.h"
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
