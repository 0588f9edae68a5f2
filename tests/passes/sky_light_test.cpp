// Sky light (passes/sky_light.h): the environment's diffuse light on open and sheltered ground, the
// world-space visibility of a roof the camera does not see, and the twin against its definition.
#include "passes/sky_light.h"

#include <catch2/catch.hpp>

#include "core/color.h"
#include "core/parallel.h"
#include "core/procedural_mesh.h"
#include "passes/gbuffer.h"
#include "passes/world_bounce.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

// A camera a metre and a half above a wide floor, looking level towards -z.
test::TestScene FloorScene(int width, int height) {
  CameraDesc camera;
  camera.position = {0.0f, 1.5f, 6.0f};
  camera.target = {0.0f, 0.0f, -4.0f};
  test::TestScene scene = test::MakeScene(camera, width, height);
  test::AddGround(scene.mesh, 40.0f);
  scene.materials[0].baseColor = glm::vec3(0.5f);
  scene.materials[0].metallic = 0.0f;
  return scene;
}

struct SkyFrame {
  GBufferOutputs gbuffer;
  SkyLightOutputs sky;
  ViewProjection view;
};

SkyFrame RenderSky(const test::TestScene& scene, const EnvironmentLighting& environment,
                   const SkyVisibilityVolume* volume, KernelPath kernels = KernelPath::kSimd) {
  SkyFrame f;
  f.view = MakePerspective(scene.camera, scene.width, scene.height);
  RunGBuffer({scene, f.view}, {scene.normalEncoding}, f.gbuffer);
  const Plane3<float> direct = MakePlane3<float>(size_t(scene.width), size_t(scene.height), 0.25f);
  RunSkyLight({f.gbuffer.gbuffer, f.view, environment, volume, direct}, {}, f.sky, kernels);
  return f;
}

// The mean of `plane` over the rows [y0, y1) of pixels with geometry.
float MeanOverRows(const Plane<float>& plane, const GBuffer& g, int y0, int y1) {
  double sum = 0.0;
  size_t n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < g.width(); ++x) {
      if (UnpackDepth(g.word[GBufferWord::kDepth].ConstRow(size_t(y))[x]) == kBackgroundDepth) continue;
      sum += plane.ConstRow(size_t(y))[x];
      ++n;
    }
  return n > 0 ? float(sum / double(n)) : 0.0f;
}

TEST_CASE("sky light: open ground under a constant sky gets albedo times the sky's radiance", "[sky_light]") {
  const test::TestScene scene = FloorScene(96, 64);
  const Environment sky = ConstantEnvironment({0.4f, 0.5f, 0.6f});
  const EnvironmentLighting lighting = PrepareEnvironmentLighting(sky);
  const SkyVisibilityVolume volume = BuildSkyVisibility(scene, {});
  const SkyFrame f = RenderSky(scene, lighting, &volume);
  // The lower half of the image is floor. A flat ground sees the whole upper hemisphere: V = 1.
  const float visibility = MeanOverRows(f.sky.visibility, f.gbuffer.gbuffer, 40, 64);
  CHECK(visibility == Approx(1.0f).margin(0.03f));
  const float diffuse = MeanOverRows(f.sky.diffuse.c[1], f.gbuffer.gbuffer, 40, 64);
  const float albedo = SrgbToLinear(LinearToSrgbCode(0.5f) / 255.0f);  // the G-buffer's 8-bit albedo
  CHECK(diffuse == Approx(albedo * 0.5f * visibility).epsilon(1e-4));
  // lit = direct + diffuse; background: lit = direct, no diffuse, V = 1.
  CHECK(f.sky.lit.c[1].ConstRow(50)[48] == 0.25f + f.sky.diffuse.c[1].ConstRow(50)[48]);
  CHECK(f.sky.visibility.ConstRow(2)[48] == 1.0f);
  CHECK(f.sky.diffuse.c[0].ConstRow(2)[48] == 0.0f);
}

// The mean of `plane` over the pixels whose world position's z lies in [zLow, zHigh]; `onlyFloor`
// is set false when a pixel shows something above the floor.
float MeanOverFloorBand(const SkyFrame& f, const Plane<float>& plane, float zLow, float zHigh, bool& onlyFloor) {
  const GBuffer& g = f.gbuffer.gbuffer;
  const glm::mat4 toWorld = glm::inverse(f.view.view);
  double sum = 0.0;
  size_t n = 0;
  for (int y = 0; y < g.height(); ++y)
    for (int x = 0; x < g.width(); ++x) {
      const float depth = UnpackDepth(g.word[GBufferWord::kDepth].ConstRow(size_t(y))[x]);
      if (depth == kBackgroundDepth) continue;
      const glm::vec3 p = glm::vec3(toWorld * glm::vec4(f.view.PixelRay(x + 0.5f, y + 0.5f).direction * depth, 1.0f));
      if (p.y > 0.01f) onlyFloor = false;
      if (p.z < zLow || p.z > zHigh) continue;
      sum += plane.ConstRow(size_t(y))[x];
      ++n;
    }
  return n > 0 ? float(sum / double(n)) : -1.0f;
}

TEST_CASE("sky light: a roof the camera does not see still blocks the sky", "[sky_light]") {
  // Looking down at the floor from 1.5 m; a roof 3 m up over z in [-30, 2], above the top of the
  // view, shelters the floor beyond z = 2.
  CameraDesc camera;
  camera.position = {0.0f, 1.5f, 6.0f};
  camera.target = {0.0f, 0.0f, 2.0f};
  test::TestScene open = test::MakeScene(camera, 96, 64);
  test::AddGround(open.mesh, 40.0f);
  test::TestScene roofed = open;
  AddBox(roofed.mesh, {-30.0f, 3.0f, -30.0f}, {30.0f, 3.2f, 2.0f});
  const EnvironmentLighting white = PrepareEnvironmentLighting(ConstantEnvironment(glm::vec3(1.0f)));
  const SkyVisibilityVolume roofedVolume = BuildSkyVisibility(roofed, {});
  const SkyVisibilityVolume openVolume = BuildSkyVisibility(open, {});
  const SkyFrame sheltered = RenderSky(roofed, white, &roofedVolume);
  const SkyFrame outside = RenderSky(open, white, &openVolume);
  const SkyFrame unknown = RenderSky(roofed, white, nullptr);
  bool onlyFloor = true;
  const float underRoof = MeanOverFloorBand(sheltered, sheltered.sky.visibility, -6.0f, -1.0f, onlyFloor);
  const float inOpen = MeanOverFloorBand(outside, outside.sky.visibility, -6.0f, -1.0f, onlyFloor);
  CAPTURE(underRoof, inOpen);
  REQUIRE(onlyFloor);  // the roof is off screen
  REQUIRE(underRoof >= 0.0f);
  CHECK(inOpen > 0.95f);
  // Under a wide roof the sky shows only towards its edges, low over the horizon.
  CHECK(underRoof < 0.3f);
  // Without the volume the sky is open everywhere.
  CHECK(MeanOverFloorBand(unknown, unknown.sky.visibility, -6.0f, -1.0f, onlyFloor) == 1.0f);
}

TEST_CASE("sky light: the visibility volume is the same at any thread count", "[sky_light]") {
  const test::DefaultScene defaults = test::LoadDefaultScene();
  const SkyVisibilityParams params{24, 128, 24};
  SkyVisibilityVolume volumes[3];
  for (int threads = 1; threads <= 3; ++threads) {
    const ThreadLimit limit(threads);
    volumes[threads - 1] = BuildSkyVisibility(defaults.scene, params);
  }
  CHECK(volumes[0].coefficients == volumes[1].coefficients);
  CHECK(volumes[0].coefficients == volumes[2].coefficients);
  CHECK(volumes[0].meshHash == MeshGeometryHash(defaults.scene.mesh));
}

TEST_CASE("sky light: the SIMD kernel gives the scalar bytes on every target", "[sky_light][simd]") {
  const test::DefaultScene defaults = test::LoadDefaultScene();
  const SkyVisibilityVolume volume = BuildSkyVisibility(defaults.scene, {24, 128, 24});
  // A sky with a glow, in small tables: its irradiance, and its radiance where pixels show it.
  SkyParams sky;
  sky.sunGlow = glm::vec3(4.0f, 3.0f, 2.0f);
  sky.sunDirection = glm::normalize(glm::vec3(0.3f, 0.5f, -0.8f));
  const EnvironmentLighting lighting = PrepareEnvironmentLighting(MakeSkyEnvironment(sky), {32, 16, 16});
  const EnvironmentLighting constant = PrepareEnvironmentLighting(ConstantEnvironment(glm::vec3(0.3f)));
  const WorldBounceVolume interreflection = BuildWorldBounce(defaults.scene, volume, lighting, {16});
  for (const auto& [width, height] : {std::pair{173, 91}, {1, 1}}) {
    const Frame frame = defaults.Render(width, height);
    for (const EnvironmentLighting* environment : {static_cast<const EnvironmentLighting*>(&lighting), &constant}) {
      for (const auto& [v, world] :
           {std::pair{&volume, &interreflection},
            {&volume, nullptr},
            {static_cast<const SkyVisibilityVolume*>(nullptr), static_cast<const WorldBounceVolume*>(nullptr)}}) {
        CAPTURE(width, height, environment->constant, v != nullptr, world != nullptr);
        const auto run = [&](KernelPath kernels) {
          SkyLightOutputs out;
          RunSkyLight({frame.gbuffer.gbuffer, frame.view, *environment, v, frame.direct.radiance, world}, {}, out,
                      kernels);
          return out;
        };
        const auto same = [](const SkyLightOutputs& a, const SkyLightOutputs& b) {
          bool equal = test::SameBytes(a.visibility, b.visibility);
          for (int c = 0; c < 3; ++c)
            equal = equal && test::SameBytes(a.diffuse.c[c], b.diffuse.c[c]) && test::SameBytes(a.lit.c[c], b.lit.c[c]);
          return equal;
        };
        CHECK(test::TargetsWhereKernelPathsDiffer(run, same).empty());
      }
    }
  }
}

}  // namespace
}  // namespace ssgi
