#include "passes/frame/frame.h"

#include <catch2/catch.hpp>

#include "core/parallel.h"
#include "core/procedural_mesh.h"
#include "passes/frame/memory.h"
#include "tests/passes/test_scenes.h"

namespace ssgi {
namespace {

std::vector<std::string> StageNames(const Frame& frame) {
  std::vector<std::string> names;
  for (const StageStats& row : StageRows(frame.stats)) names.push_back(row.name);
  return names;
}

// A box on a glossy ground under a shadow-casting sun: every pass of the frame runs.
test::TestScene BoxOnGlossyGround(int width, int height) {
  CameraDesc camera;
  camera.position = {0.0f, 2.0f, 4.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  test::TestScene scene = test::MakeScene(camera, width, height);
  test::AddGround(scene.mesh, 5.0f);
  test::AddBox(scene.mesh, {-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f});
  scene.directionalLights.push_back(test::Sun(test::LightDirection(30.0f, 40.0f), 2.0f));
  scene.materials[0].roughness = 0.2f;
  return scene;
}

TEST_CASE("the frame's stats list the stages that ran, in pipeline order", "[frame]") {
  const test::TestScene scene = BoxOnGlossyGround(48, 32);

  // Under its black sky the sun's light still goes round through the interreflection volume.
  FrameConfig config = test::ConfigOf(scene);
  const Frame all = RenderFrame(scene, config);
  CHECK(StageNames(all) == std::vector<std::string>{"g-buffer raster", "g-buffer resolve", "frame plan", "shadow map",
                                                    "blocker search", "shadow filter", "direct light",
                                                    "sky visibility", "interreflection volume", "sky light", "hi-z",
                                                    "colour pyramid", "ssr trace", "cone trace", "composite",
                                                    "antialias", "tonemap", "frame total"});
  REQUIRE(all.stats.tonemap);
  CHECK(all.stats.tonemap->pixels == 48 * 32);
  REQUIRE(all.stats.gbuffer);
  CHECK(all.stats.gbuffer->coveredPixels > 0);
  REQUIRE(all.stats.ssrTrace);
  CHECK(all.stats.ssrTrace->rays > 0);

  config.shadows = EffectMode::kOff;
  config.reflections = EffectMode::kOff;
  config.sky = EffectMode::kOff;
  config.bounce = EffectMode::kOff;
  const Frame direct = RenderFrame(scene, config);
  CHECK(StageNames(direct) == std::vector<std::string>{"g-buffer raster", "g-buffer resolve", "frame plan",
                                                       "direct light", "antialias", "tonemap", "frame total"});
  CHECK(!direct.stats.shadowMap);
  CHECK(!direct.stats.composite);
}

TEST_CASE("sky_directions 0: the frame makes no sky visibility volume, opens the sky everywhere and counts none",
          "[frame][sky_light]") {
  test::TestScene scene = BoxOnGlossyGround(48, 32);
  scene.background = glm::vec3(0.3f);
  FrameConfig config = test::ConfigOf(scene);
  const Frame withVolume = RenderFrame(scene, config, BufferLifetime::kKeepAll);
  ApplySetting(config, "sky_directions", "0");
  const Frame without = RenderFrame(scene, config, BufferLifetime::kKeepAll);
  REQUIRE(withVolume.skyVolume.has_value());
  CHECK(!without.skyVolume.has_value());
  REQUIRE(without.stats.skyLight);
  float lowest = 1.0f;
  for (size_t y = 0; y < 32; ++y)
    for (size_t x = 0; x < 48; ++x) lowest = std::min(lowest, without.skyLight.visibility.ConstRow(y)[x]);
  CHECK(lowest == 1.0f);
  // The box shelters the ground next to it only through the volume.
  float lowestWith = 1.0f;
  for (size_t y = 0; y < 32; ++y)
    for (size_t x = 0; x < 48; ++x) lowestWith = std::min(lowestWith, withVolume.skyLight.visibility.ConstRow(y)[x]);
  CHECK(lowestWith < 0.9f);
  FrameConfig volumeConfig = config;
  ApplySetting(volumeConfig, "sky_directions", "48");
  CHECK(EstimateFrameMemory(scene, config, BufferLifetime::kKeepAll).bytes <
        EstimateFrameMemory(scene, volumeConfig, BufferLifetime::kKeepAll).bytes);
}

TEST_CASE("a frame that frees each buffer after its last reader gives the same image", "[frame][memory]") {
  const test::TestScene scene = BoxOnGlossyGround(64, 48);
  const FrameConfig config = test::ConfigOf(scene);
  const Frame kept = RenderFrame(scene, config, BufferLifetime::kKeepAll);
  const Frame freed = RenderFrame(scene, config, BufferLifetime::kUntilLastReader);
  REQUIRE(freed.reflections);
  CHECK(freed.display.rgb == kept.display.rgb);
  for (int c = 0; c < 3; ++c) CHECK(test::SameBytes(freed.Result().c[c], kept.Result().c[c]));
  // Only the G-buffer words, the result and the display image outlive the passes.
  CHECK(freed.hiz.levels.empty());
  CHECK(freed.colorPyramid.levels.empty());
  CHECK(freed.direct.radiance.c[0].xsize() == 0);
  CHECK(freed.ssrCone.reflected.c[0].xsize() == 0);
  CHECK(freed.ssrTrace.hitX.xsize() == 0);
  CHECK(freed.ssrTrace.iterations.xsize() == 0);  // never recorded: no dump reads it
  CHECK(freed.composite.indirect.c[0].xsize() == 0);
  CHECK_FALSE(freed.shadowMap);
  CHECK(freed.gbuffer.visibility.triangle.xsize() == 0);
}

TEST_CASE("a frame with the bounce and the sky light gives the same bytes at 1, 2 and 3 threads, freed or kept",
          "[frame][determinism]") {
  test::TestScene scene = BoxOnGlossyGround(67, 45);
  scene.background = glm::vec3(0.2f, 0.3f, 0.4f);
  FrameConfig config = test::ConfigOf(scene);
  config.bounce = EffectMode::kOn;  // in `auto` the interreflection volume stands for it
  std::optional<Frame> first;
  for (int threads : {1, 2, 3}) {
    CAPTURE(threads);
    const ThreadLimit limit(threads);
    Frame kept = RenderFrame(scene, config, BufferLifetime::kKeepAll);
    REQUIRE(kept.bounce);
    REQUIRE(kept.sky);
    REQUIRE(kept.reflections);
    const Frame freed = RenderFrame(scene, config, BufferLifetime::kUntilLastReader);
    CHECK(freed.display.rgb == kept.display.rgb);
    Frame reused;
    for (int i = 0; i < 2; ++i)
      RunFramePasses(scene, config, FramePass::kGBuffer, FramePass::kTonemap, reused, BufferLifetime::kKeepForReuse);
    CHECK(reused.display.rgb == kept.display.rgb);
    for (int c = 0; c < 3; ++c) {
      CHECK(test::SameBytes(freed.Result().c[c], kept.Result().c[c]));
      CHECK(test::SameBytes(reused.Result().c[c], kept.Result().c[c]));
    }
    if (!first) {
      first = std::move(kept);
      continue;
    }
    CHECK(kept.display.rgb == first->display.rgb);
    CHECK(test::SameBytes(kept.diffuseBounce.visibility, first->diffuseBounce.visibility));
    CHECK(test::SameBytes(kept.diffuseBounce.half.visibility, first->diffuseBounce.half.visibility));
    for (int c = 0; c < 3; ++c) {
      CHECK(test::SameBytes(kept.diffuseBounce.bounce.c[c], first->diffuseBounce.bounce.c[c]));
      CHECK(test::SameBytes(kept.composite.indirect.c[c], first->composite.indirect.c[c]));
      CHECK(test::SameBytes(kept.Result().c[c], first->Result().c[c]));
    }
  }
}

// A rough box on rough ground, and a glossy strip in front of the box that reflects it: a small
// share of the image, whose cones read levels above 0.
test::TestScene GlossyStripBeforeBox(int width, int height) {
  test::TestScene scene = BoxOnGlossyGround(width, height);
  scene.materials[0].roughness = 0.9f;
  Material glossy = scene.materials[0];
  glossy.roughness = 0.2f;
  glossy.metallic = 1.0f;
  scene.materials.push_back(glossy);
  AddQuad(scene.mesh, {-0.6f, 0.001f, 1.3f}, {1.2f, 0.0f, 0.0f}, {0.0f, 0.0f, -0.5f}, 1u);
  return scene;
}

TEST_CASE("a frame with few reflecting pixels makes part of the colour pyramid, with the same image",
          "[frame][memory][plan]") {
  // Texels the partial pyramid does not make stay 0, so a cone that read one would change the image.
  const test::TestScene scene = GlossyStripBeforeBox(192, 128);
  const FrameConfig config = test::ConfigOf(scene);
  const Frame kept = RenderFrame(scene, config, BufferLifetime::kKeepAll);
  const Frame freed = RenderFrame(scene, config, BufferLifetime::kUntilLastReader);
  REQUIRE(freed.reflections);
  REQUIRE(freed.plan.reflections.pixels * 10 <= freed.plan.pixels);
  REQUIRE(kept.stats.ssrCone);
  CHECK(kept.stats.ssrCone->pixels > 100);
  REQUIRE(freed.stats.colorPyramid);
  CHECK(freed.stats.colorPyramid->texels < kept.stats.colorPyramid->texels);
  CHECK(freed.display.rgb == kept.display.rgb);
  for (int c = 0; c < 3; ++c) CHECK(test::SameBytes(freed.Result().c[c], kept.Result().c[c]));
  // Kept for the next frame, as a renderer keeps them: the same, frame after frame.
  Frame reused;
  for (int i = 0; i < 2; ++i) {
    RunFramePasses(scene, config, FramePass::kGBuffer, FramePass::kTonemap, reused, BufferLifetime::kKeepForReuse);
    REQUIRE(reused.stats.colorPyramid);
    CHECK(reused.stats.colorPyramid->texels < kept.stats.colorPyramid->texels);
    CHECK(reused.display.rgb == kept.display.rgb);
    for (int c = 0; c < 3; ++c) CHECK(test::SameBytes(reused.Result().c[c], kept.Result().c[c]));
  }
}

TEST_CASE("a frame kept for reuse renders other scenes into the same buffers, each with its own image",
          "[frame][memory][plan]") {
  // Mostly glossy, then a glossy strip: what the second leaves unwritten holds the first's buffers.
  const test::TestScene scenes[] = {BoxOnGlossyGround(192, 128), GlossyStripBeforeBox(192, 128)};
  Frame reused;
  for (int i = 0; i < 4; ++i) {
    const test::TestScene& scene = scenes[i % 2];
    const FrameConfig config = test::ConfigOf(scene);
    const Frame fresh = RenderFrame(scene, config, BufferLifetime::kKeepAll);
    RunFramePasses(scene, config, FramePass::kGBuffer, FramePass::kTonemap, reused, BufferLifetime::kKeepForReuse);
    CAPTURE(i);
    REQUIRE(reused.reflections);
    CHECK(reused.display.rgb == fresh.display.rgb);
    for (int c = 0; c < 3; ++c) CHECK(test::SameBytes(reused.Result().c[c], fresh.Result().c[c]));
  }
}

TEST_CASE("a frame rendered again into its kept buffers gives the same image", "[frame]") {
  const test::TestScene scene = BoxOnGlossyGround(64, 48);
  const FrameConfig config = test::ConfigOf(scene);
  const Frame fresh = RenderFrame(scene, config);
  Frame kept;
  for (int i = 0; i < 2; ++i) RunFramePasses(scene, config, FramePass::kGBuffer, FramePass::kTonemap, kept);
  REQUIRE(kept.shadowMap);
  CHECK(kept.display.rgb == fresh.display.rgb);
  CHECK(test::SameBytes(kept.gbuffer.gbuffer.word[GBufferWord::kShadowTerm],
                        fresh.gbuffer.gbuffer.word[GBufferWord::kShadowTerm]));
  // Kept for reuse: the composite in place, its planes trading places frame after frame.
  Frame reused;
  for (int i = 0; i < 3; ++i) {
    RunFramePasses(scene, config, FramePass::kGBuffer, FramePass::kTonemap, reused, BufferLifetime::kKeepForReuse);
    REQUIRE(reused.reflections);
    CHECK(reused.display.rgb == fresh.display.rgb);
    for (int c = 0; c < 3; ++c) CHECK(test::SameBytes(reused.Result().c[c], fresh.Result().c[c]));
  }
}

}  // namespace
}  // namespace ssgi
