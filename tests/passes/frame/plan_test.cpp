// The frame plan (passes/frame/plan.h): effects planned from the visible pixels, skipped where no
// pixel needs them, with the image's bytes as if they had run; forced modes still force.
#include "passes/frame/plan.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "passes/direct_light.h"
#include "passes/frame/frame.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

constexpr int kWidth = 96, kHeight = 64;

// A rough floor seen from above and in front, lit by a shadow-casting sun from above.
test::TestScene RoughFloor(int width = kWidth, int height = kHeight) {
  CameraDesc camera;
  camera.position = {0.0f, 2.0f, 5.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  test::TestScene scene = test::MakeScene(camera, width, height);
  scene.materials[0].roughness = 0.9f;
  test::AddGround(scene.mesh, 50.0f);
  scene.directionalLights.push_back(test::Sun(test::LightDirection(30.0f, 40.0f), 2.0f));
  return scene;
}

// Adds a box of a new material of that roughness.
void AddBoxOfRoughness(test::TestScene& scene, glm::vec3 lo, glm::vec3 hi, float roughness) {
  Material smooth = scene.materials[0];
  smooth.roughness = roughness;
  scene.materials.push_back(smooth);
  test::AddBox(scene.mesh, lo, hi, uint32_t(scene.materials.size() - 1));
}

Frame Render(const test::TestScene& scene, EffectMode shadows, EffectMode reflections) {
  FrameConfig config = test::ConfigOf(scene);
  config.shadows = shadows;
  config.reflections = reflections;
  return RenderFrame(scene, config);
}

TEST_CASE("frame plan: a smooth surface off screen or covered does not run the reflections", "[plan]") {
  SECTION("behind the camera") {
    test::TestScene scene = RoughFloor();
    AddBoxOfRoughness(scene, {-1.0f, 0.0f, 8.0f}, {1.0f, 1.0f, 9.0f}, 0.1f);
    const Frame autoFrame = Render(scene, EffectMode::kAuto, EffectMode::kAuto);
    CHECK_FALSE(autoFrame.plan.reflections.run);
    CHECK(autoFrame.plan.reflections.why.find("no visible surface is smoother") == 0);
    CHECK(autoFrame.plan.reflections.pixels == 0);
    CHECK_FALSE(autoFrame.stats.ssrTrace);
    const Frame forced = Render(scene, EffectMode::kAuto, EffectMode::kOn);
    CHECK(forced.plan.reflections.run);
    CHECK(forced.plan.reflections.why == "switched on");
    REQUIRE(forced.stats.ssrTrace);
    // Nothing on screen reflects, so the skipped passes would have added nothing.
    CHECK(autoFrame.display.rgb == forced.display.rgb);
  }
  SECTION("beside the view") {
    test::TestScene scene = RoughFloor();
    AddBoxOfRoughness(scene, {-30.0f, 0.0f, -1.0f}, {-28.0f, 2.0f, 1.0f}, 0.1f);
    const Frame frame = Render(scene, EffectMode::kAuto, EffectMode::kAuto);
    CHECK_FALSE(frame.plan.reflections.run);
    CHECK(frame.display.rgb == Render(scene, EffectMode::kAuto, EffectMode::kOn).display.rgb);
  }
  SECTION("covered by a rough wall") {
    test::TestScene scene = RoughFloor();
    AddBoxOfRoughness(scene, {-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f}, 0.1f);
    CHECK(Render(scene, EffectMode::kAuto, EffectMode::kAuto).plan.reflections.run);
    test::AddQuad(scene.mesh, {-20.0f, -20.0f, 3.0f}, {40.0f, 0.0f, 0.0f}, {0.0f, 40.0f, 0.0f});
    const Frame covered = Render(scene, EffectMode::kAuto, EffectMode::kAuto);
    CHECK(covered.plan.geometryPixels == size_t(kWidth) * kHeight);
    CHECK_FALSE(covered.plan.reflections.run);
    CHECK(covered.display.rgb == Render(scene, EffectMode::kAuto, EffectMode::kOn).display.rgb);
  }
  SECTION("in view: the share of tiles and pixels") {
    test::TestScene scene = RoughFloor();
    AddBoxOfRoughness(scene, {-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f}, 0.1f);
    const Frame frame = Render(scene, EffectMode::kAuto, EffectMode::kAuto);
    CHECK(frame.plan.reflections.run);
    CHECK(frame.plan.reflections.pixels > 0);
    CHECK(frame.plan.reflections.pixels < frame.plan.geometryPixels);
    CHECK(frame.plan.reflections.tiles >= 1);
    CHECK(frame.plan.reflections.tiles < frame.plan.tiles);
    CHECK(frame.stats.ssrTrace);
  }
}

TEST_CASE("frame plan: a shadow-casting light that reaches no visible pixel runs no shadow pass", "[plan]") {
  test::TestScene scene = RoughFloor();
  // The sun shines up from below the floor: no visible pixel faces it.
  scene.directionalLights[0].direction = glm::vec3(0.2f, 1.0f, 0.1f) / glm::length(glm::vec3(0.2f, 1.0f, 0.1f));
  const Frame autoFrame = Render(scene, EffectMode::kAuto, EffectMode::kAuto);
  CHECK_FALSE(autoFrame.plan.shadows.run);
  CHECK(autoFrame.plan.shadows.why == "no visible pixel faces the shadow-casting light");
  CHECK_FALSE(autoFrame.stats.shadowMap);
  CHECK_FALSE(autoFrame.stats.shadowFilter);
  const Frame forced = Render(scene, EffectMode::kOn, EffectMode::kAuto);
  CHECK(forced.plan.shadows.run);
  CHECK(forced.stats.shadowMap);
  CHECK(autoFrame.display.rgb == forced.display.rgb);
  // Lit from above, the same floor runs them; switched off, it does not.
  scene.directionalLights[0].direction = test::LightDirection(30.0f, 40.0f);
  CHECK(Render(scene, EffectMode::kAuto, EffectMode::kAuto).plan.shadows.run);
  const Frame off = Render(scene, EffectMode::kOff, EffectMode::kAuto);
  CHECK_FALSE(off.plan.shadows.run);
  CHECK(off.plan.shadows.why == "switched off");
}

TEST_CASE("frame plan: a light no visible pixel faces is not shaded, and the image is the same", "[plan]") {
  test::TestScene scene = RoughFloor();
  scene.directionalLights[0].castShadows = false;
  // Spot 1 lights the floor in view; spot 2 is aimed at the sky; spot 3 lights the floor from below
  // it (the floor in its cone faces away); a second sun shines from below the floor.
  scene.spotLights.push_back(test::Spot({0.0f, 3.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, 30.0f, 0.1f));
  scene.spotLights.push_back(test::Spot({0.0f, 3.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 30.0f, 0.1f));
  scene.spotLights.push_back(test::Spot({0.0f, -2.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 40.0f, 0.1f));
  scene.directionalLights.push_back(test::Sun(glm::normalize(glm::vec3(0.2f, 1.0f, 0.1f)), 1.0f));
  const Frame frame = Render(scene, EffectMode::kAuto, EffectMode::kAuto);
  // PrepareLights order: the suns, then the spots.
  CHECK(frame.plan.lightReaches == std::vector<bool>{true, false, true, false, false});
  const std::string text = ExplainPlan(frame.plan);
  CHECK(text.find("lights: 2 of 5 face a visible pixel and are shaded; not shaded (no visible pixel faces it): "
                  "directional light 2, spot light 2, spot light 3") != std::string::npos);
  // Every light shaded gives the same bytes: the left-out lights add exactly 0.
  DirectLightOutputs all;
  RunDirectLight({frame.gbuffer.gbuffer, frame.view, scene}, {}, all);
  for (int c = 0; c < 3; ++c) CHECK(test::SameBytes(all.radiance.c[c], frame.direct.radiance.c[c]));
  // And the mask does leave lights out: without the spot that lights the floor, the floor is darker.
  const std::vector<bool> withoutSpot = {true, false, false, false, false};
  DirectLightInputs masked{frame.gbuffer.gbuffer, frame.view, scene};
  masked.shadeLights = &withoutSpot;
  DirectLightOutputs dimmer;
  RunDirectLight(masked, {}, dimmer);
  CHECK_FALSE(test::SameBytes(dimmer.radiance.c[0], frame.direct.radiance.c[0]));
}

TEST_CASE("frame plan: the explanation counts what each effect touches", "[plan]") {
  test::TestScene scene = RoughFloor();
  AddBoxOfRoughness(scene, {-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f}, 0.1f);
  const Frame frame = Render(scene, EffectMode::kAuto, EffectMode::kAuto);
  const FramePlan counted =
      PlanFrame(scene, test::ConfigOf(scene), frame.gbuffer.gbuffer, frame.gbuffer.edgeCoverage, frame.view, true);
  CHECK(counted.shadows.counted);
  CHECK(counted.shadows.pixels > 0);
  CHECK(counted.shadows.pixels <= counted.geometryPixels);
  CHECK(counted.reflections.pixels == frame.plan.reflections.pixels);
  const std::string text = ExplainPlan(counted);
  CHECK(text.find("shadows: run, visible pixels face the shadow-casting light; needed in") != std::string::npos);
  CHECK(text.find("reflections: run") != std::string::npos);
  // The sun lights the floor under a black sky, so the sky light runs for its interreflection volume,
  // which stands for the bounce, and with it the composite on the whole image.
  CHECK(text.find("hi-z, colour pyramid run; ssr trace, cone trace run on those " +
                  std::to_string(counted.reflections.tiles) + " tiles only") != std::string::npos);
  CHECK(text.find("sky: run, the environment is black, but lights reach visible surfaces: the interreflection "
                  "volume carries their light between surfaces\n    sky light runs on every pixel with geometry") !=
        std::string::npos);
  CHECK(text.find("bounce: skipped, the interreflection volume carries the bounced light\n    bounce does not run\n") !=
        std::string::npos);
  // Without the sky light and the bounce, the composite works on the traced tiles alone.
  FrameConfig config = test::ConfigOf(scene);
  config.sky = EffectMode::kOff;
  config.bounce = EffectMode::kOff;
  const std::string withoutBounce =
      ExplainPlan(PlanFrame(scene, config, frame.gbuffer.gbuffer, frame.gbuffer.edgeCoverage, frame.view));
  CHECK(withoutBounce.find("hi-z, colour pyramid run; ssr trace, cone trace, composite run on those " +
                           std::to_string(counted.reflections.tiles) + " tiles only") != std::string::npos);
  CHECK(withoutBounce.find("bounce: skipped, switched off\n    bounce does not run\n") != std::string::npos);
  CHECK(withoutBounce.find("sky: skipped, switched off\n    sky light does not run\n") != std::string::npos);
}

TEST_CASE("frame plan: the bounce runs where something on screen is lit, and costs nothing where nothing is",
          "[plan]") {
  test::TestScene scene = RoughFloor();
  AddBoxOfRoughness(scene, {-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f}, 0.9f);
  int interreflectionDirections = WorldBounceParams{}.directions;
  const auto render = [&](EffectMode bounce) {
    FrameConfig config = test::ConfigOf(scene);
    config.bounce = bounce;
    config.interreflection.directions = interreflectionDirections;
    return RenderFrame(scene, config);
  };
  SECTION("a light reaches visible surfaces, and no interreflection volume carries its bounce") {
    interreflectionDirections = 0;
    const Frame frame = render(EffectMode::kAuto);
    CHECK_FALSE(frame.plan.sky.run);
    CHECK(frame.plan.sky.why == "the environment is black");
    CHECK(frame.plan.bounce.run);
    CHECK(frame.plan.bounce.why == "lights reach visible surfaces");
    REQUIRE(frame.stats.bounce);
    CHECK(frame.stats.bounce->pixels == size_t(kWidth) * kHeight);
    REQUIRE(frame.stats.composite);  // the bounce's light reaches the image through the composite
    // The box's light bounces onto the floor beside it, and the floor's onto the box.
    CHECK_FALSE(test::SameBytes(frame.Result().c[0], frame.direct.radiance.c[0]));
    const Frame off = render(EffectMode::kOff);
    CHECK_FALSE(off.plan.bounce.run);
    CHECK(off.plan.bounce.why == "switched off");
    CHECK_FALSE(off.stats.bounce);
    CHECK_FALSE(off.stats.composite);
  }
  SECTION("the interreflection volume carries the bounced light") {
    scene.background = glm::vec3(0.2f, 0.3f, 0.4f);
    const Frame frame = render(EffectMode::kAuto);
    CHECK(frame.plan.sky.run);
    REQUIRE(frame.interreflection);
    CHECK_FALSE(frame.plan.bounce.run);
    CHECK(frame.plan.bounce.why == "the interreflection volume carries the bounced light");
    CHECK_FALSE(frame.stats.bounce);
    CHECK(frame.diffuseBounce.visibility.xsize() == 0);
    // Forced on, it runs over the volume's light.
    const Frame forced = render(EffectMode::kOn);
    REQUIRE(forced.stats.bounce);
    CHECK_FALSE(test::SameBytes(frame.Result().c[2], forced.Result().c[2]));
  }
  SECTION("the sky alone lights them, without an interreflection volume") {
    scene.directionalLights.clear();
    scene.background = glm::vec3(0.2f, 0.3f, 0.4f);
    interreflectionDirections = 0;
    const Frame frame = render(EffectMode::kAuto);
    CHECK(frame.plan.sky.run);
    CHECK(frame.plan.bounce.run);
    CHECK(frame.plan.bounce.why == "the sky lights the visible surfaces");
    CHECK(ExplainPlan(frame.plan).find("and darkens the sky's diffuse light by its visibility") != std::string::npos);
    // The box and the floor occlude each other's sky and light each other.
    const Frame off = render(EffectMode::kOff);
    CHECK_FALSE(test::SameBytes(frame.Result().c[2], off.Result().c[2]));
  }
  SECTION("nothing is lit") {
    // The sun shines from below the floor, and the environment is black.
    scene.directionalLights[0].direction = glm::normalize(glm::vec3(0.2f, 1.0f, 0.1f));
    const Frame frame = render(EffectMode::kAuto);
    CHECK_FALSE(frame.plan.bounce.run);
    CHECK(frame.plan.bounce.why ==
          "nothing on screen is lit (no light reaches a visible pixel and the sky light does not run)");
    CHECK(ExplainPlan(frame.plan).find("bounce: skipped, nothing on screen is lit") != std::string::npos);
    // It costs nothing: the pass does not run and holds no memory, and neither does the composite.
    CHECK_FALSE(frame.stats.bounce);
    CHECK_FALSE(frame.stats.composite);
    CHECK(frame.diffuseBounce.bounce.c[0].xsize() == 0);
    CHECK(frame.diffuseBounce.visibility.xsize() == 0);
    CHECK(frame.diffuseBounce.half.depth.xsize() == 0);
    // Forced on, it would have added nothing.
    const Frame forced = render(EffectMode::kOn);
    CHECK(forced.plan.bounce.why == "switched on");
    REQUIRE(forced.stats.bounce);
    CHECK(forced.display.rgb == frame.display.rgb);
    for (int c = 0; c < 3; ++c) CHECK(test::SameBytes(forced.Result().c[c], frame.Result().c[c]));
  }
  SECTION("no pixel has geometry") {
    scene.mesh = {};
    const Frame frame = render(EffectMode::kAuto);
    CHECK_FALSE(frame.plan.bounce.run);
    CHECK(frame.plan.bounce.why == "no pixel has geometry");
    CHECK_FALSE(frame.plan.sky.run);
    CHECK(frame.plan.sky.why == "no pixel has geometry");
  }
  SECTION("under a black sky the lights' light goes round through the interreflection volume") {
    const Frame frame = render(EffectMode::kAuto);
    CHECK(frame.plan.sky.run);
    CHECK(frame.plan.sky.why == "the environment is black, but lights reach visible surfaces: the interreflection "
                                "volume carries their light between surfaces");
    REQUIRE(frame.interreflection);
    CHECK_FALSE(frame.plan.bounce.run);
    // The box's sunlit faces light the floor beside it, and the floor the box: more light than the
    // direct light alone, and exactly the direct light on the background.
    FrameConfig config = test::ConfigOf(scene);
    config.sky = EffectMode::kOff;
    config.bounce = EffectMode::kOff;
    const Frame direct = RenderFrame(scene, config);
    double with = 0.0, without = 0.0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        with += frame.Result().c[1].ConstRow(size_t(y))[x];
        without += direct.Result().c[1].ConstRow(size_t(y))[x];
      }
    CHECK(with > without * 1.01);
  }
}

TEST_CASE("frame plan: the tile counts' twin gives the scalar counts on every target", "[plan][simd]") {
  std::mt19937 rng(7);
  for (int width : {1, 31, 32, 67, 1023}) {
    // Background, geometry at both ends of the depth range, every roughness code.
    std::vector<uint32_t> word1(static_cast<size_t>(width)), word2(static_cast<size_t>(width));
    for (int x = 0; x < width; ++x) {
      word1[size_t(x)] = uint32_t(rng());
      const uint32_t kind = rng() % 4;
      word2[size_t(x)] = kind == 0 ? PackDepth(kBackgroundDepth) : kind == 1 ? PackDepth(1e-6f) : PackDepth(3.5f);
    }
    for (uint32_t smoothCodes : {0u, 1u, 77u, 255u, 256u}) {
      const size_t tiles = size_t((width + TileMask::kTileSize - 1) / TileMask::kTileSize);
      std::vector<uint32_t> geometry(tiles, 5), smooth(tiles, 3);  // the kernels add to what is there
      CountPlanRowScalar(word1.data(), word2.data(), width, smoothCodes, geometry.data(), smooth.data());
      uint32_t covered = 0;
      for (uint32_t n : geometry) covered += n - 5;
      CHECK(covered == uint32_t(std::count_if(word2.begin(), word2.end(),
                                               [](uint32_t w) { return w != PackDepth(kBackgroundDepth); })));
      const size_t targets = test::ForEachSimdTarget([&](const char* target) {
        std::vector<uint32_t> simdGeometry(tiles, 5), simdSmooth(tiles, 3);
        CountPlanRowSimd(word1.data(), word2.data(), width, smoothCodes, simdGeometry.data(), simdSmooth.data());
        CAPTURE(target, width, smoothCodes);
        CHECK(simdGeometry == geometry);
        CHECK(simdSmooth == smooth);
      });
      CHECK(targets >= 1);
    }
  }
}

TEST_CASE("frame plan: the reflection tiles are the tiles with a smooth pixel", "[plan]") {
  test::TestScene scene = RoughFloor();
  AddBoxOfRoughness(scene, {-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f}, 0.1f);
  const Frame frame = Render(scene, EffectMode::kAuto, EffectMode::kAuto);
  const TileMask& tiles = frame.plan.reflectionTiles;
  REQUIRE(tiles.Fits(kWidth, kHeight));
  const GBuffer& gbuffer = frame.gbuffer.gbuffer;
  size_t needed = 0;
  for (int tileY = 0; tileY < tiles.tilesY; ++tileY) {
    for (int tileX = 0; tileX < tiles.tilesX; ++tileX) {
      bool smooth = false;
      for (int y = tileY * TileMask::kTileSize; y < std::min(kHeight, (tileY + 1) * TileMask::kTileSize); ++y) {
        for (int x = tileX * TileMask::kTileSize; x < std::min(kWidth, (tileX + 1) * TileMask::kTileSize); ++x) {
          const uint32_t word1 = gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(size_t(y))[x];
          const bool geometry =
              UnpackDepth(gbuffer.word[GBufferWord::kDepth].ConstRow(size_t(y))[x]) != kBackgroundDepth;
          smooth = smooth || (geometry && UnpackRoughness(word1) < test::ConfigOf(scene).ssrTrace.roughnessCutoff);
        }
      }
      CAPTURE(tileX, tileY);
      CHECK(tiles.Needed(tileX, tileY) == smooth);
      needed += smooth;
    }
  }
  CHECK(needed == frame.plan.reflections.tiles);
  CHECK(needed > 0);
  CHECK(needed < tiles.needed.size());
}

TEST_CASE("frame plan: the trace, cone and composite skipping tiles give the bytes of the whole image", "[plan]") {
  // Whole tiles, and tiles cut at the right and bottom edges.
  const auto [width, height] = GENERATE(std::pair{kWidth, kHeight}, std::pair{101, 70});
  test::TestScene scene = RoughFloor(width, height);
  AddBoxOfRoughness(scene, {-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f}, 0.1f);
  // Without the bounce and the sky light, whose light reaches every pixel, the composite skips tiles too.
  FrameConfig config = test::ConfigOf(scene);
  config.sky = EffectMode::kOff;
  config.bounce = EffectMode::kOff;
  const Frame frame = RenderFrame(scene, config);  // every buffer kept, the passes given the tiles
  REQUIRE(frame.reflections);
  REQUIRE(frame.plan.reflections.tiles < frame.plan.tiles);
  const GBuffer& gbuffer = frame.gbuffer.gbuffer;
  SsrTraceOutputs trace;
  RunSsrTrace({gbuffer, frame.view, frame.hiz}, config.ssrTrace, trace);
  CHECK(test::SameBytes(trace.hitX, frame.ssrTrace.hitX));
  CHECK(test::SameBytes(trace.hitY, frame.ssrTrace.hitY));
  CHECK(test::SameBytes(trace.confidence, frame.ssrTrace.confidence));
  CHECK(test::SameBytes(trace.iterations, frame.ssrTrace.iterations));
  for (const KernelPath kernels : {KernelPath::kScalar, KernelPath::kSimd}) {
    SsrConeOutputs cone;
    RunSsrCone({gbuffer, frame.colorPyramid, trace.hitX, trace.hitY, trace.confidence}, config.ssrCone, cone, kernels);
    SsrConeOutputs skipping;
    RunSsrCone({gbuffer, frame.colorPyramid, trace.hitX, trace.hitY, trace.confidence, &frame.plan.reflectionTiles},
               config.ssrCone, skipping, kernels);
    CompositeOutputs composite, skippingComposite;
    RunComposite({gbuffer, frame.view, frame.direct.radiance, &cone.reflected, &trace.confidence,
                  config.ssrTrace.roughnessCutoff},
                 composite, kernels);
    RunComposite({gbuffer, frame.view, frame.direct.radiance, &cone.reflected, &trace.confidence,
                  config.ssrTrace.roughnessCutoff, &frame.plan.reflectionTiles},
                 skippingComposite, kernels);
    for (int c = 0; c < 3; ++c) {
      CAPTURE(int(kernels), c);
      CHECK(test::SameBytes(skipping.reflected.c[c], cone.reflected.c[c]));
      CHECK(test::SameBytes(cone.reflected.c[c], frame.ssrCone.reflected.c[c]));
      CHECK(test::SameBytes(skippingComposite.indirect.c[c], composite.indirect.c[c]));
      CHECK(test::SameBytes(skippingComposite.result.c[c], composite.result.c[c]));
      CHECK(test::SameBytes(composite.result.c[c], frame.composite.result.c[c]));
    }
  }
}

}  // namespace
}  // namespace ssgi
