// The interreflection volume (passes/world_bounce.h): a sunlit floor's light on a wall the sun does
// not reach, against the form factor of a half-space; the same volume at any thread count; kept
// while the scene, its lights and the environment hold.
#include "passes/world_bounce.h"

#include <catch2/catch.hpp>

#include "core/brdf.h"
#include "core/parallel.h"
#include "core/procedural_mesh.h"
#include "tests/passes/test_scenes.h"

namespace ssgi {
namespace {

// A wide grey floor of albedo `floorAlbedo` under a sun straight overhead, and a black wall 6 m high
// across it at z in [-0.5, 0], whose face towards +z the sun does not light.
test::TestScene WallBesideSunlitFloor(float floorAlbedo) {
  CameraDesc camera;
  camera.position = {0.0f, 2.0f, 10.0f};
  camera.target = {0.0f, 2.0f, 0.0f};
  test::TestScene scene = test::MakeScene(camera, 64, 64);
  test::AddGround(scene.mesh, 30.0f);
  scene.materials[0].baseColor = glm::vec3(floorAlbedo);
  scene.materials[0].metallic = 0.0f;
  Material wall = scene.materials[0];
  wall.baseColor = glm::vec3(0.0f);
  scene.materials.push_back(wall);
  AddBox(scene.mesh, {-30.0f, 0.0f, -0.5f}, {30.0f, 6.0f, 0.0f}, 1);
  scene.directionalLights = {DirectionalLight{{0.0f, -1.0f, 0.0f}, glm::vec3(4.0f), 0.53f, true}};
  return scene;
}

float ReadInterreflection(const WorldBounceVolume& volume, const SkyVisibilityVolume& grid, const glm::vec3& p,
                          const glm::vec3& n) {
  return ReadVolume(volume.coefficients[0].data(), SampleVolume(grid, p, n));
}

TEST_CASE("interreflection: a wall beside a sunlit floor gets half the floor's radiance", "[world_bounce]") {
  const float albedo = 0.2f;
  const test::TestScene scene = WallBesideSunlitFloor(albedo);
  const SkyVisibilityVolume grid = BuildSkyVisibility(scene, {24, 128, 48});
  const EnvironmentLighting black = PrepareEnvironmentLighting(ConstantEnvironment(glm::vec3(0.0f)));
  const WorldBounceVolume volume = BuildWorldBounce(scene, grid, black, {});
  // The floor's radiance L = albedo E / pi fills the lower half of the wall's hemisphere: E_w / pi =
  // L / 2. The enclosure's further bounces add at most 1 / (1 - albedo / 2) (the floor is half the
  // cell's directions, the black wall reflects nothing).
  const float floorRadiance = albedo * 4.0f / kPi;
  for (const float height : {1.5f, 3.0f}) {
    const float onWall = ReadInterreflection(volume, grid, {0.0f, height, 0.0f}, {0.0f, 0.0f, 1.0f});
    CAPTURE(height, onWall, floorRadiance);
    CHECK(onWall > 0.8f * 0.5f * floorRadiance);
    CHECK(onWall < 1.2f * 0.5f * floorRadiance / (1.0f - albedo / 2.0f));
  }
  // Far from the wall the floor sees only the black sky: 0 but for the 64-direction quadrature's
  // error in the floor's own half-space, which the first two SH bands cancel only exactly.
  CHECK(std::abs(ReadInterreflection(volume, grid, {0.0f, 0.0f, 20.0f}, {0.0f, 1.0f, 0.0f})) < 0.03f * floorRadiance);
  // The wall's back, in the shadow of nothing but facing a floor the sun lights too.
  CHECK(ReadInterreflection(volume, grid, {0.0f, 1.5f, -0.5f}, {0.0f, 0.0f, -1.0f}) > 0.8f * 0.5f * floorRadiance);
}

TEST_CASE("interreflection: the volume is the same at any thread count", "[world_bounce]") {
  const test::DefaultScene defaults = test::LoadDefaultScene();
  const SkyVisibilityVolume grid = BuildSkyVisibility(defaults.scene, {24, 128, 16});
  const EnvironmentLighting sky = PrepareEnvironmentLighting(defaults.config.environment, {32, 16, 16});
  WorldBounceVolume volumes[3];
  for (int threads = 1; threads <= 3; ++threads) {
    const ThreadLimit limit(threads);
    volumes[threads - 1] = BuildWorldBounce(defaults.scene, grid, sky, {16});
  }
  for (int c = 0; c < 3; ++c) {
    CHECK(volumes[0].coefficients[size_t(c)] == volumes[1].coefficients[size_t(c)]);
    CHECK(volumes[0].coefficients[size_t(c)] == volumes[2].coefficients[size_t(c)]);
  }
}

TEST_CASE("interreflection: the volume is kept while the scene, its lights and the environment hold",
          "[world_bounce]") {
  test::TestScene scene = WallBesideSunlitFloor(0.5f);
  const SkyVisibilityVolume grid = BuildSkyVisibility(scene, {8, 64, 12});
  const EnvironmentLighting black = PrepareEnvironmentLighting(ConstantEnvironment(glm::vec3(0.0f)));
  const EnvironmentLighting grey = PrepareEnvironmentLighting(ConstantEnvironment(glm::vec3(0.5f)));
  const WorldBounceParams params{8};
  const WorldBounceVolume volume = BuildWorldBounce(scene, grid, black, params);
  CHECK(WorldBounceHolds(volume, scene, grid, black, params));
  CHECK_FALSE(WorldBounceHolds(volume, scene, grid, grey, params));
  CHECK_FALSE(WorldBounceHolds(volume, scene, grid, black, WorldBounceParams{16}));
  test::TestScene moved = scene;
  moved.directionalLights[0].direction = glm::normalize(glm::vec3(0.2f, -1.0f, 0.0f));
  CHECK_FALSE(WorldBounceHolds(volume, moved, grid, black, params));
  test::TestScene brighter = scene;
  brighter.directionalLights[0].irradiance = glm::vec3(5.0f);
  CHECK_FALSE(WorldBounceHolds(volume, brighter, grid, black, params));
}

}  // namespace
}  // namespace ssgi
