#include "passes/shadow_map.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <random>
#include <vector>

#include "core/closed_surfaces.h"
#include "core/parallel.h"
#include "core/raster/scene_raster_input.h"
#include "passes/gbuffer.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

using test::AddBox;
using test::AddGround;
using test::AddQuad;
using test::LightDirection;
using test::MakeScene;
using test::TestScene;

using test::Sun;

struct Rendered {
  ViewProjection camera;
  GBufferOutputs g;
  VisibilityBuffer shadowMap;
  ViewProjection lightView;
  ShadowMapStats stats;

  uint32_t Term(int x, int y) const { return g.gbuffer.word[GBufferWord::kShadowTerm].ConstRow(y)[x]; }
  bool Background(int x, int y) const {
    return !(UnpackDepth(g.gbuffer.word[GBufferWord::kDepth].ConstRow(y)[x]) < kBackgroundDepth);
  }
  glm::vec3 World(int x, int y) const { return test::WorldPosition(camera, g.gbuffer, x, y); }
};

Rendered Render(const test::TestScene& scene, const ShadowMapParams& params = {}, size_t light = 0) {
  Rendered r;
  r.camera = MakePerspective(scene.camera, scene.width, scene.height);
  RunGBuffer({scene, r.camera}, {scene.normalEncoding}, r.g);
  ShadowMapOutputs out;
  r.stats =
      RunShadowMap({scene, r.camera, r.g.gbuffer, light}, params, out, r.g.gbuffer.word[GBufferWord::kShadowTerm]);
  r.shadowMap = std::move(out.shadowMap);
  r.lightView = out.lightView;
  return r;
}

// Every word 3 decodes to a finite distance >= 0, background pixels are lit, and every depth key is
// finite in [0, 1].
bool AllValid(const Rendered& r) {
  for (int y = 0; y < r.g.gbuffer.height(); ++y) {
    for (int x = 0; x < r.g.gbuffer.width(); ++x) {
      const float d = UnpackBlockerDistance(r.Term(x, y));
      if (!(std::isfinite(d) && d >= 0.0f)) return false;
      if (r.Background(x, y) && r.Term(x, y) != kShadowLit) return false;
    }
  }
  for (size_t y = 0; y < r.shadowMap.depthKey.ysize(); ++y)
    for (size_t x = 0; x < r.shadowMap.depthKey.xsize(); ++x) {
      const float key = r.shadowMap.depthKey.ConstRow(y)[x];
      if (!(key >= 0.0f && key <= 1.0f)) return false;
    }
  const glm::mat4& m = r.lightView.viewProjection;
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 4; ++k)
      if (!std::isfinite(m[c][k])) return false;
  return true;
}

// Does the ray from p along `toLight` pass through the box [lo, hi]? Slab test.
bool RayHitsBox(glm::vec3 p, glm::vec3 toLight, glm::vec3 lo, glm::vec3 hi) {
  float t0 = 0.0f, t1 = std::numeric_limits<float>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (std::fabs(toLight[a]) < 1e-12f) {
      if (p[a] < lo[a] || p[a] > hi[a]) return false;
      continue;
    }
    float ta = (lo[a] - p[a]) / toLight[a], tb = (hi[a] - p[a]) / toLight[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}

bool OnGround(glm::vec3 p) { return std::fabs(p.y) < 1e-3f; }

TEST_CASE("shadow map: a lit plane has no acne at any light angle", "[shadow]") {
  CameraDesc camera;
  camera.position = {0.0f, 3.0f, 6.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  for (NormalEncoding encoding : {NormalEncoding::kOct24, NormalEncoding::kXyz8}) {
    for (int resolution : {2048, 512, 97}) {
      for (float angle : {0.0f, 30.0f, 60.0f, 80.0f}) {
        for (float azimuth : {0.0f, 37.0f, 200.0f}) {
          TestScene scene = MakeScene(camera, 160, 120);
          scene.normalEncoding = encoding;
          AddGround(scene.mesh, 20.0f);
          scene.directionalLights.push_back(Sun(LightDirection(angle, azimuth), 5.0f));
          ShadowMapParams params;
          params.resolution = resolution;
          const Rendered r = Render(scene, params);
          size_t notLit = 0, ground = 0;
          for (int y = 0; y < 120; ++y)
            for (int x = 0; x < 160; ++x) {
              ground += !r.Background(x, y);
              notLit += r.Term(x, y) != kShadowLit;
            }
          CAPTURE(int(encoding), resolution, angle, azimuth);
          CHECK(ground > 5000);
          CHECK(r.stats.pixels == ground);
          CHECK(notLit == 0);
        }
      }
    }
  }
}

TEST_CASE("shadow map: a slab above a plane gives the hard flag and the blocker distance", "[shadow]") {
  const float angle = 30.0f;
  const glm::vec3 dir = LightDirection(angle, 0.0f);
  const glm::vec3 lo(-0.5f, 0.5f, -0.5f), hi(0.5f, 0.52f, 0.5f);
  // The shadow of the slab's centre on the ground.
  const glm::vec3 centre = glm::vec3(0.0f, 0.51f, 0.0f) + dir * (0.51f / -dir.y);
  CameraDesc camera;  // below the slab, looking at its shadow
  camera.position = {centre.x, 0.3f, 2.0f};
  camera.target = centre;
  TestScene scene = MakeScene(camera, 400, 300);
  AddGround(scene.mesh, 5.0f);
  AddBox(scene.mesh, lo, hi);
  scene.directionalLights.push_back(Sun(dir, 2.0f));
  const Rendered r = Render(scene);
  REQUIRE(AllValid(r));

  // The shadow map stores the surface nearest the light, the slab's top; Fernando's blocker depth.
  const float gapTop = hi.y / -dir.y, gapBottom = lo.y / -dir.y;
  size_t underCentre = 0, hardUnder = 0, umbra = 0, hardUmbra = 0, clear = 0, litClear = 0;
  double worstTop = 0.0, worstBottom = 0.0;
  const glm::vec3 shrink(0.03f, 0.0f, 0.03f);  // texels and the 2 degree light's penumbra
  for (int y = 0; y < 300; ++y) {
    for (int x = 0; x < 400; ++x) {
      if (r.Background(x, y)) continue;
      const glm::vec3 p = r.World(x, y);
      if (!OnGround(p)) continue;
      const uint32_t term = r.Term(x, y);
      if (glm::length(p - centre) < 0.2f) {
        ++underCentre;
        hardUnder += UnpackHardShadow(term);
        const double d = UnpackBlockerDistance(term);
        worstTop = std::max(worstTop, std::fabs(d - gapTop) / gapTop);
        worstBottom = std::max(worstBottom, std::fabs(d - gapBottom) / gapBottom);
      }
      // Analytic visibility of the light's centre, with margins for texels and the penumbra.
      if (RayHitsBox(p, -dir, lo + shrink, hi - shrink)) {
        ++umbra;
        hardUmbra += UnpackHardShadow(term);
      }
      if (!RayHitsBox(p, -dir, lo - glm::vec3(0.1f), hi + glm::vec3(0.1f))) {
        ++clear;
        litClear += term == kShadowLit;
      }
    }
  }
  WARN("slab gap " << gapTop << " m (top), " << gapBottom << " m (bottom): worst relative error "
                   << worstTop << " (top), " << worstBottom << " (bottom) over " << underCentre << " pixels");
  CHECK(underCentre > 500);
  CHECK(hardUnder == underCentre);
  CHECK(worstTop < 0.05);
  CHECK(worstBottom < 0.05);
  CHECK(umbra > 2000);
  CHECK(hardUmbra == umbra);
  CHECK(clear > 2000);
  CHECK(litClear == clear);
}

TEST_CASE("shadow map: a caster resting on the plane shadows from the contact (no peter-panning)", "[shadow]") {
  // Light travelling +x at 45 degrees: the shadow lies on x > 0.5, beside the caster's +x side.
  const glm::vec3 dir = LightDirection(45.0f, 0.0f);
  CameraDesc camera;  // straight down onto the contact edge, just on its shadow side
  camera.position = {0.52f, 1.2f, 0.0f};
  camera.target = {0.52f, 0.0f, 0.0f};
  camera.up = {0.0f, 0.0f, -1.0f};
  camera.fovYDegrees = 15.0f;
  // A solid box, whose light-facing faces are far from the ground beside its base, and a wall of
  // zero thickness, the strict case: the blocker's depth meets the receiver's at the contact.
  for (bool wall : {false, true}) {
    TestScene scene = MakeScene(camera, 400, 400);
    AddGround(scene.mesh, 5.0f);
    if (wall) {
      AddQuad(scene.mesh, {0.5f, 0.0f, -0.5f}, {0.0f, 0.0f, 1.0f}, {0.0f, 0.5f, 0.0f});
    } else {
      AddBox(scene.mesh, {-0.5f, 0.0f, -0.5f}, {0.5f, 0.5f, 0.5f});
    }
    scene.directionalLights.push_back(Sun(dir, 1.0f));
    for (int resolution : {32, 64, 128}) {
      ShadowMapParams params;
      params.resolution = resolution;
      const Rendered r = Render(scene, params);
      REQUIRE(AllValid(r));
      // Texel size in the light's image plane; its footprint on the ground along x is 1 / cos 45 longer.
      const float texel = 2.0f * r.lightView.halfX / float(resolution);
      float lastLit = 0.5f;  // the largest x of a ground pixel in the shadow's first half that is lit
      size_t inShadow = 0;
      float pixel = 0.0f;
      for (int y = 0; y < 400; ++y) {
        for (int x = 0; x < 400; ++x) {
          if (r.Background(x, y)) continue;
          const glm::vec3 p = r.World(x, y);
          if (!OnGround(p) || p.x <= 0.5f || p.x > 0.75f || std::fabs(p.z) > 0.3f) continue;
          ++inShadow;
          if (x + 1 < 400) pixel = std::max(pixel, std::fabs(r.World(x + 1, y).x - p.x));
          if (!UnpackHardShadow(r.Term(x, y))) lastLit = std::max(lastLit, p.x);
        }
      }
      const float gap = lastLit - 0.5f;
      const float gapTexels = gap * std::cos(glm::radians(45.0f)) / texel;
      WARN((wall ? "wall" : "box") << ", map " << resolution << ": texel " << texel * 1000.0f << " mm, camera pixel "
                                   << pixel * 1000.0f << " mm on the ground; lit gap at the contact "
                                   << gap * 1000.0f << " mm = " << gapTexels << " texels");
      CHECK(inShadow > 5000);
      CHECK(pixel < 0.3f * texel);
      CHECK(gapTexels <= 1.0f);
    }
  }
}

TEST_CASE("shadow map: casters outside the camera's view still cast", "[shadow]") {
  CameraDesc camera;  // looking straight down from below the box
  camera.position = {0.0f, 0.8f, 0.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  camera.up = {0.0f, 0.0f, -1.0f};
  camera.fovYDegrees = 40.0f;
  TestScene scene = MakeScene(camera, 64, 64);
  AddGround(scene.mesh, 5.0f);
  AddBox(scene.mesh, {-1.5f, 1.0f, -1.0f}, {-1.0f, 1.5f, 1.0f});
  scene.directionalLights.push_back(Sun(LightDirection(45.0f, 0.0f), 1.0f));
  const Rendered r = Render(scene);
  REQUIRE(AllValid(r));
  size_t hard = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      REQUIRE(OnGround(r.World(x, y)));  // the box is not in view
      hard += UnpackHardShadow(r.Term(x, y));
    }
  CHECK(hard == 64u * 64u);
}

TEST_CASE("shadow map: spot light blocker distance along the light's rays", "[shadow]") {
  const glm::vec3 lightPos(0.0f, 3.0f, 0.0f);
  const glm::vec3 lo(-0.5f, 1.0f, -0.5f), hi(0.5f, 1.02f, 0.5f);
  CameraDesc camera;
  camera.position = {0.0f, 0.4f, 3.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  TestScene scene = MakeScene(camera, 200, 150);
  AddGround(scene.mesh, 5.0f);
  AddBox(scene.mesh, lo, hi);
  SpotLight spot;
  spot.position = lightPos;
  spot.direction = {0.0f, -1.0f, 0.0f};
  spot.outerConeDegrees = 40.0f;
  spot.innerConeDegrees = 30.0f;
  spot.radius = 0.05f;
  scene.spotLights.push_back(spot);
  ShadowMapParams params;
  params.resolution = 1024;
  const Rendered r = Render(scene, params);
  REQUIRE(AllValid(r));
  CHECK(!r.lightView.orthographic);
  CHECK(r.lightView.nearPlane == Approx(0.99f * (3.0f - 1.02f)));
  size_t under = 0, hard = 0, outside = 0, litOutside = 0;
  double worst = 0.0;
  for (int y = 0; y < 150; ++y) {
    for (int x = 0; x < 200; ++x) {
      if (r.Background(x, y)) continue;
      const glm::vec3 p = r.World(x, y);
      if (!OnGround(p)) continue;
      const uint32_t term = r.Term(x, y);
      const float horizontal = std::max(std::fabs(p.x), std::fabs(p.z));
      if (horizontal < 0.4f) {
        ++under;
        hard += UnpackHardShadow(term);
        // Similar triangles: the part of the ray from p to the light below the slab's top.
        const double expected = glm::length(lightPos - p) * hi.y / lightPos.y;
        worst = std::max(worst, std::fabs(UnpackBlockerDistance(term) - expected) / expected);
      }
      // Outside the square frustum (fov 80 deg: |x| or |z| > 3 tan 40 on the ground): lit.
      if (horizontal > 3.0f * std::tan(glm::radians(40.0f)) + 0.05f) {
        ++outside;
        litOutside += term == kShadowLit;
      }
    }
  }
  WARN("spot: worst relative blocker distance error " << worst << " over " << under << " pixels");
  CHECK(under > 200);
  CHECK(hard == under);
  CHECK(worst < 0.05);
  CHECK(outside > 500);
  CHECK(litOutside == outside);
}

// The default scene at the given size; light 0 is its sun (orthographic map), light 1 a spot light
// (perspective map) whose cone leaves part of the scene outside its map.
TestScene DefaultSceneWithSpot(int width, int height) {
  TestScene scene = test::Sized(LoadScene(test::SourceDir() / "data" / "default.json"), width, height);
  scene.spotLights.push_back(test::Spot({0.5f, 2.5f, 1.0f}, {-0.2f, -1.0f, -0.4f}, 50.0f, 0.1f));
  return scene;
}

TEST_CASE("shadow map: closed casters' back faces are culled and every depth is the both-faces map's", "[shadow]") {
  const TestScene scene = DefaultSceneWithSpot(161, 119);
  const ClosedSurfaces closed = FindClosedSurfaces(scene.mesh);
  CHECK(closed.lo.size() >= 9);  // the pieces, spheres and boxes (the board is open)
  ShadowMapParams params;
  params.resolution = 1024;
  for (size_t light : {size_t(0), size_t(1)}) {
    const Rendered r = Render(scene, params, light);
    VisibilityBuffer bothFaces = MakeVisibilityBuffer(1024, 1024, RasterOutput::kDepthOnly);
    const SceneRasterInput raster(scene, r.lightView, false);
    const RasterStats both = Rasterize(raster.Get(), r.lightView, RasterOutput::kDepthOnly, bothFaces, nullptr);
    CAPTURE(light);
    CHECK(test::SameBytes(r.shadowMap.depthKey, bothFaces.depthKey));
    CHECK(r.stats.raster.trianglesCulled > both.trianglesCulled + 2000);
  }
}

TEST_CASE("shadow map: a spot light inside a closed box is shut in by its walls", "[shadow]") {
  CameraDesc camera;
  camera.position = {0.0f, 0.4f, 3.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  TestScene scene = MakeScene(camera, 120, 90);
  AddGround(scene.mesh, 5.0f);
  AddBox(scene.mesh, glm::vec3(-0.3f, 2.7f, -0.3f), glm::vec3(0.3f, 3.3f, 0.3f));  // around the light
  scene.spotLights.push_back(test::Spot({0.0f, 3.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, 40.0f, 0.05f));
  REQUIRE(FindClosedSurfaces(scene.mesh).lo.size() == 1);
  const Rendered r = Render(scene, {}, 0);
  REQUIRE(AllValid(r));
  size_t lit = 0, underCone = 0;
  for (int y = 0; y < 90; ++y) {
    for (int x = 0; x < 120; ++x) {
      if (r.Background(x, y) || !OnGround(r.World(x, y))) continue;
      const glm::vec3 p = r.World(x, y);
      if (std::max(std::fabs(p.x), std::fabs(p.z)) > 1.5f) continue;  // well inside the cone
      ++underCone;
      lit += !UnpackHardShadow(r.Term(x, y));
    }
  }
  CHECK(underCone > 500);
  CHECK(lit == 0);
}

TEST_CASE("shadow map: identical bits at 1, 2 and 3 threads", "[shadow]") {
  const TestScene scene = DefaultSceneWithSpot(161, 119);
  ShadowMapParams params;
  params.resolution = 517;
  for (size_t light : {size_t(0), size_t(1)}) {
    std::vector<Rendered> runs;
    for (int threads : {1, 2, 3}) {
      ThreadLimit limit(threads);
      runs.push_back(Render(scene, params, light));
    }
    size_t shadowed = 0;
    for (int y = 0; y < 119; ++y) {
      for (const Rendered& run : runs)
        REQUIRE(std::memcmp(run.g.gbuffer.word[GBufferWord::kShadowTerm].ConstRow(y),
                            runs[0].g.gbuffer.word[GBufferWord::kShadowTerm].ConstRow(y), 161 * 4) == 0);
      for (int x = 0; x < 161; ++x) shadowed += UnpackHardShadow(runs[0].Term(x, y));
    }
    for (size_t y = 0; y < 517; ++y)
      for (const Rendered& run : runs)
        REQUIRE(std::memcmp(run.shadowMap.depthKey.ConstRow(y), runs[0].shadowMap.depthKey.ConstRow(y), 517 * 4) == 0);
    CAPTURE(light);
    CHECK(shadowed > 100);  // the comparison is about something
    CHECK(AllValid(runs[0]));
  }
}

TEST_CASE("shadow map: no NaN or Inf at grazing and degenerate set-ups", "[shadow]") {
  CameraDesc camera;
  camera.position = {0.3f, 1.5f, 3.0f};
  camera.target = {0.0f, 0.2f, 0.0f};
  auto boxScene = [&](int width, int height) {
    TestScene scene = MakeScene(camera, width, height);
    AddGround(scene.mesh, 4.0f);
    AddBox(scene.mesh, {-0.3f, 0.0f, -0.3f}, {0.3f, 0.6f, 0.3f});
    return scene;
  };
  SECTION("grazing, horizontal and upward lights") {
    for (glm::vec3 dir : {LightDirection(89.9f, 10.0f), LightDirection(90.0f, 0.0f), glm::vec3(0.0f, 0.0f, -1.0f),
                          glm::vec3(0.0f, 1.0f, 0.0f), LightDirection(179.0f, 45.0f)}) {
      TestScene scene = boxScene(97, 61);
      scene.directionalLights.push_back(Sun(dir, 10.0f));
      CAPTURE(dir.x, dir.y, dir.z);
      CHECK(AllValid(Render(scene)));
    }
  }
  SECTION("tiny images and maps: every pixel is a border pixel") {
    for (int size : {1, 2, 7}) {
      for (int resolution : {1, 3, 64}) {
        TestScene scene = boxScene(size, size + 1);
        scene.directionalLights.push_back(Sun(LightDirection(40.0f, 30.0f), 3.0f));
        ShadowMapParams params;
        params.resolution = resolution;
        CAPTURE(size, resolution);
        CHECK(AllValid(Render(scene, params)));
      }
    }
  }
  SECTION("one tap and many taps, huge light") {
    for (int taps : {1, 2, kMaxBlockerSearchTaps}) {
      TestScene scene = boxScene(64, 48);
      scene.directionalLights.push_back(Sun(LightDirection(20.0f, 0.0f), 60.0f));
      ShadowMapParams params;
      params.blockerSearchTaps = taps;
      params.resolution = 256;
      CAPTURE(taps);
      CHECK(AllValid(Render(scene, params)));
    }
  }
  SECTION("empty scene") {
    TestScene scene = MakeScene(camera, 33, 17);
    scene.directionalLights.push_back(Sun(LightDirection(30.0f, 0.0f), 1.0f));
    ShadowMapParams params;
    params.resolution = 64;
    const Rendered r = Render(scene, params);
    CHECK(r.stats.pixels == 0);
    CHECK(r.shadowMap.depthKey.xsize() == 64);
    CHECK(AllValid(r));
  }
  SECTION("receivers outside a spot light's map are lit") {
    for (glm::vec3 axis : {glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(1.0f, 0.0f, 0.0f)}) {
      TestScene scene = boxScene(80, 60);
      SpotLight spot;
      spot.position = {0.0f, 0.3f, 0.0f};  // inside the box, pointing out of it
      spot.direction = axis;
      spot.outerConeDegrees = 89.0f;  // clamped to a 170 degree field of view
      spot.innerConeDegrees = 80.0f;
      spot.radius = 0.5f;
      scene.spotLights.push_back(spot);
      const Rendered r = Render(scene);
      REQUIRE(AllValid(r));
      size_t lit = 0;
      for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 80; ++x) {
          if (r.Background(x, y)) continue;
          const glm::vec3 p = r.World(x, y);
          // Behind the light (the ground for the upward light) is outside the map: lit.
          if (glm::dot(p - spot.position, axis) <= 0.0f) {
            CHECK(r.Term(x, y) == kShadowLit);
            ++lit;
          }
        }
      CAPTURE(axis.x, axis.y);
      CHECK(lit > 100);
    }
  }
}

TEST_CASE("shadow map: the SIMD blocker search equals the scalar definition on every compiled target",
          "[shadow][simd]") {
  size_t targets = 0, shadowed = 0;
  for (NormalEncoding encoding : {NormalEncoding::kOct24, NormalEncoding::kXyz8}) {
    TestScene scene = DefaultSceneWithSpot(161, 119);
    scene.normalEncoding = encoding;
    const ViewProjection camera = MakePerspective(scene.camera, scene.width, scene.height);
    GBufferOutputs g;
    RunGBuffer({scene, camera}, {encoding}, g);
    const std::vector<PreparedLight> lights = PrepareLights(scene, glm::mat4(1.0f));
    for (size_t light : {size_t(0), size_t(1)}) {
      // A fine map, and a coarse one whose search radius reaches past its edges.
      for (int resolution : {517, 29}) {
        ShadowMapParams params;
        params.resolution = resolution;
        ShadowMapOutputs out;
        RunShadowMap({scene, camera, g.gbuffer, light}, params, out, g.gbuffer.word[GBufferWord::kShadowTerm]);
        const ReceiverPositions receivers(camera, out.lightView.view * glm::inverse(camera.view));
        for (int taps : {16, 3}) {
          const std::vector<glm::vec2> pattern = BlockerSearchPattern(taps);
          const BlockerSearchContext context =
              MakeBlockerSearchContext(receivers, out, lights[light], pattern, params.maxBlockerDistance, encoding);
          std::vector<uint32_t> expected(size_t(scene.width)), actual(size_t(scene.width) + 1);
          // Whole rows, and on every third row pieces of every length from 1 to 64 pixels (several
          // vectors and a tail on every target) starting anywhere in the row.
          auto check = [&](const char* target, int y, int start, int length) {
            const uint32_t* word1 = g.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(y) + start;
            const uint32_t* word2 = g.gbuffer.word[GBufferWord::kDepth].ConstRow(y) + start;
            BlockerSearchRowScalar(context, word1, word2, y, length, expected.data());
            std::fill(actual.begin(), actual.end(), 0xABABABABu);
            BlockerSearchRowSimd(context, word1, word2, y, length, actual.data());
            CAPTURE(target, int(encoding), light, resolution, taps, y, start, length);
            REQUIRE(std::equal(expected.begin(), expected.begin() + length, actual.begin()));
            REQUIRE(actual[size_t(length)] == 0xABABABABu);
          };
          targets += test::ForEachSimdTarget([&](const char* target) {
            for (int y = 0; y < scene.height; ++y) {
              check(target, y, 0, scene.width);
              if (y % 3 != 0) continue;
              for (int length = 1; length <= 64; ++length)
                check(target, y, (y * 31 + length * 7) % (scene.width - length), length);
            }
          });
          for (int y = 0; y < scene.height; ++y) {
            BlockerSearchRowScalar(context, g.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(y),
                                   g.gbuffer.word[GBufferWord::kDepth].ConstRow(y), y, scene.width, expected.data());
            for (uint32_t term : expected) shadowed += UnpackHardShadow(term);
          }
        }
      }
    }
  }
  CHECK(targets >= 2 * 2 * 2 * 2 * 2);  // at least two targets (one SIMD) per case
  CHECK(shadowed > 5000);               // the comparison is about something
}

TEST_CASE("shadow map: the SIMD blocker search writes the scalar word 3 on every compiled target", "[shadow][simd]") {
  for (glm::ivec2 size : {glm::ivec2(kDefaultImageSide), glm::ivec2(1, 1), glm::ivec2(67, 45), glm::ivec2(1023, 769)}) {
    const TestScene scene = DefaultSceneWithSpot(size.x, size.y);
    const ViewProjection camera = MakePerspective(scene.camera, size.x, size.y);
    GBufferOutputs g;
    RunGBuffer({scene, camera}, {scene.normalEncoding}, g);
    // The scene's own sun, as frames render it; the spot light (covered row by row above) at 67x45.
    for (size_t light = 0; light < (size.x == 67 ? 2u : 1u); ++light) {
      for (int taps : {1, 4, 16, 64}) {
        ShadowMapParams params;
        params.blockerSearchTaps = taps;
        ShadowMapOutputs out;
        Plane<uint32_t> expected = MakePlane<uint32_t>(size.x, size.y, 0u);
        RunShadowMap({scene, camera, g.gbuffer, light}, params, out, expected, KernelPath::kScalar);
        size_t shadowed = 0;
        for (int y = 0; y < size.y; ++y)
          for (int x = 0; x < size.x; ++x) shadowed += expected.ConstRow(y)[x] != kShadowLit;
        CAPTURE(size.x, size.y, light, taps);
        CHECK((shadowed > 0 || size.x == 1));  // the comparison is about something
        test::ForEachSimdTarget([&](const char* target) {
          Plane<uint32_t> actual = MakePlane<uint32_t>(size.x, size.y, 0xABABABABu);
          RunShadowMap({scene, camera, g.gbuffer, light}, params, out, actual, KernelPath::kSimd);
          CAPTURE(target);
          REQUIRE(test::SameBytes(actual, expected));
        });
      }
    }
  }
}

TEST_CASE("shadow map: the SIMD receiver bounds equal the scalar definition on every compiled target",
          "[shadow][simd]") {
  // Rows of view depths with background pixels, and positions that land on -0 and +0 exactly (a
  // light view through the camera, so x = 0 on the centre column and depth 0 at the origin) or on
  // NaN (an infinite step): the bounds must not depend on the order the pixels are visited in.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> depth(0.5f, 40.0f);
  std::uniform_int_distribution<int> background(0, 5);
  const std::vector<ReceiverPositions::Row> rows = {
      {{-0.7f, 0.3f, -1.0f}, {0.011f, 0.0f, 0.0f}},
      {{-0.0f, 0.0f, -0.0f}, {0.0f, -0.0f, 0.0f}},
      {{0.2f, -0.4f, -1.0f}, {std::numeric_limits<float>::infinity(), 0.001f, -0.002f}}};
  const TestScene scene = DefaultSceneWithSpot(64, 48);
  const ViewProjection camera = MakePerspective(scene.camera, 64, 48);
  size_t targets = 0;
  for (const glm::mat4& toLight : {glm::mat4(1.0f), glm::lookAt(glm::vec3(1.0f, 2.0f, 3.0f), glm::vec3(0.0f),
                                                                 glm::vec3(0.0f, 1.0f, 0.0f))}) {
    const ReceiverPositions positions(camera, toLight);
    for (const ReceiverPositions::Row& row : rows) {
      for (int width : {1, 7, 16, 33, 200}) {
        std::vector<uint32_t> word2(static_cast<size_t>(width));
        for (uint32_t& w : word2) w = PackDepth(background(rng) == 0 ? kBackgroundDepth : depth(rng));
        glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
        const size_t count = ReceiverBoundsRowScalar(word2.data(), width, positions, row, lo, hi);
        targets += test::ForEachSimdTarget([&](const char* target) {
          glm::vec3 simdLo(std::numeric_limits<float>::infinity()), simdHi(-std::numeric_limits<float>::infinity());
          CAPTURE(target, width);
          CHECK(ReceiverBoundsRowSimd(word2.data(), width, positions, row, simdLo, simdHi) == count);
          CHECK(std::memcmp(&simdLo, &lo, sizeof(lo)) == 0);
          CHECK(std::memcmp(&simdHi, &hi, sizeof(hi)) == 0);
        });
      }
    }
  }
  CHECK(targets >= 2 * 3 * 5 * 2);
}

TEST_CASE("shadow map: the first shadow-casting light is listed first", "[shadow]") {
  Scene scene;
  scene.directionalLights.resize(2);
  scene.directionalLights[0].castShadows = false;
  scene.spotLights.resize(2);
  scene.spotLights[1].castShadows = false;
  CHECK(ShadowCastingLights(scene) == std::vector<size_t>{1, 2});
  scene.directionalLights[1].castShadows = false;
  CHECK(ShadowCastingLights(scene) == std::vector<size_t>{2});
}

}  // namespace
}  // namespace ssgi
