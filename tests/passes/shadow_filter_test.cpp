#include "passes/shadow_filter.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <catch2/catch.hpp>

#include "core/parallel.h"
#include "passes/gbuffer.h"
#include "tests/passes/test_scenes.h"
#include "passes/shadow_map.h"

namespace ssgi {
namespace {

using test::AddBox;
using test::AddGround;
using test::AddQuad;
using test::LightDirection;
using test::MakeScene;
using test::TestScene;

void AddSun(Scene& scene, glm::vec3 direction, float angularDiameterDegrees) {
  scene.directionalLights.push_back(test::Sun(direction, angularDiameterDegrees));
}

CameraDesc Camera(glm::vec3 position, glm::vec3 target, glm::vec3 up, float fovYDegrees) {
  CameraDesc c;
  c.position = position;
  c.target = target;
  c.up = up;
  c.fovYDegrees = fovYDegrees;
  return c;
}

// The G-buffer with word 3 from the shadow map, ready to filter.
struct Rendered {
  test::TestScene scene;
  ViewProjection camera;
  GBufferOutputs g;
  PreparedLight light;

  bool Background(int x, int y) const { return !(UnpackDepth(g.gbuffer.word[2].ConstRow(y)[x]) < kBackgroundDepth); }
  bool Hard(int x, int y) const { return UnpackHardShadow(g.gbuffer.word[3].ConstRow(y)[x]); }
  glm::vec3 World(int x, int y) const { return test::WorldPosition(camera, g.gbuffer, x, y); }
  glm::vec2 Screen(glm::vec3 world) const {
    const glm::vec4 clip = camera.viewProjection * glm::vec4(world, 1.0f);
    return {(clip.x / clip.w * 0.5f + 0.5f) * float(camera.width),
            (0.5f - clip.y / clip.w * 0.5f) * float(camera.height)};
  }
};

Rendered Render(test::TestScene scene) {
  Rendered r;
  r.scene = std::move(scene);
  r.camera = MakePerspective(r.scene.camera, r.scene.width, r.scene.height);
  RunGBuffer({r.scene, r.camera}, {r.scene.normalEncoding}, r.g);
  ShadowMapOutputs out;
  RunShadowMap({r.scene, r.camera, r.g.gbuffer, 0}, {}, out, r.g.gbuffer.word[3]);
  r.light = PrepareLights(r.scene, r.camera.view)[0];
  return r;
}

Plane<float> Filter(const Rendered& r, ShadowFilter filter, int maxRadius = 24) {
  ShadowFilterParams params;
  params.filter = filter;
  params.maxRadiusPixels = maxRadius;
  ShadowFilterOutputs out;
  RunShadowFilter({r.g.gbuffer, r.camera, r.light}, params, out);
  return std::move(out.visibility);
}

struct Edge {
  bool found = false;
  double world = 0.0;  // metres between the 0.1 and 0.9 crossings
  double pixels = 0.0;
};

// The width of the shadow edge that column `x` crosses near row `aroundRow`: the distance between
// the (linearly interpolated) points where visibility crosses 0.1 and 0.9, nearest the 0.5 crossing.
Edge MeasureEdge(const Rendered& r, const Plane<float>& vis, int x, int aroundRow, int window) {
  std::vector<float> v;
  std::vector<glm::vec3> p;
  const int y0 = std::max(0, aroundRow - window), y1 = std::min(r.camera.height - 1, aroundRow + window);
  for (int y = y0; y <= y1; ++y) {
    v.push_back(vis.ConstRow(y)[x]);
    p.push_back(r.World(x, y));
  }
  auto crossing = [&](float level, double near, double& at) {
    bool found = false;
    for (size_t j = 0; j + 1 < v.size(); ++j) {
      if ((v[j] - level) * (v[j + 1] - level) > 0.0f || v[j] == v[j + 1]) continue;
      const double f = double(j) + double(level - v[j]) / double(v[j + 1] - v[j]);
      if (!found || std::fabs(f - near) < std::fabs(at - near)) at = f;
      found = true;
    }
    return found;
  };
  auto point = [&](double f) {
    const size_t j = std::min(size_t(f), p.size() - 2);
    return glm::mix(glm::dvec3(p[j]), glm::dvec3(p[j + 1]), f - double(j));
  };
  Edge e;
  double half = 0, lo = 0, hi = 0;
  if (!crossing(0.5f, double(aroundRow - y0), half) || !crossing(0.1f, half, lo) || !crossing(0.9f, half, hi)) return e;
  e.found = true;
  e.world = glm::length(point(hi) - point(lo));
  e.pixels = std::fabs(hi - lo);
  return e;
}

// A box filter turns a straight hard edge into a linear ramp of width w; its 0.1-0.9 part is 0.8 w.
constexpr double kRampTenToNinety = 0.8;

// A 2 cm slab at height h over the half space z < 0, lit from straight above: its edge's shadow lies
// along x at z = 0, with the PCSS penumbra width w = (h + 0.01) * 2 tan(angular radius).
TestScene SlabScene(const CameraDesc& camera, float height, float angularDiameter) {
  TestScene scene = MakeScene(camera, 256, 192);
  AddGround(scene.mesh, 5.0f);
  AddBox(scene.mesh, {-2.0f, height, -2.0f}, {2.0f, height + 0.02f, 0.0f});
  AddSun(scene, {0.0f, -1.0f, 0.0f}, angularDiameter);
  return scene;
}

double AnalyticWidth(float height, float angularDiameter) {
  return (double(height) + 0.01) * 2.0 * std::tan(glm::radians(double(angularDiameter)) * 0.5);
}

// Mean 0.1-0.9 width over five columns around the image centre crossing the edge at z = 0.
double MeanEdgeWidth(const Rendered& r, const Plane<float>& vis) {
  double sum = 0.0;
  for (int dx : {-40, -20, 0, 20, 40}) {
    const glm::vec2 s = r.Screen({0.0f, 0.0f, 0.0f});
    const Edge e = MeasureEdge(r, vis, int(s.x) + dx, int(s.y), 60);
    REQUIRE(e.found);
    sum += e.world;
  }
  return sum / 5.0;
}

TEST_CASE("shadow filter: penumbra width matches PCSS and grows with light size and gap", "[shadow_filter]") {
  const CameraDesc top = Camera({0.0f, 0.45f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 45.0f);
  double previous = 0.0;
  for (const auto& [height, diameter] : {std::pair{0.5f, 4.0f}, {0.5f, 8.0f}, {0.8f, 8.0f}}) {
    const Rendered r = Render(SlabScene(top, height, diameter));
    const double measured = MeanEdgeWidth(r, Filter(r, ShadowFilter::kSsabss, 64)) / kRampTenToNinety;
    const double expected = AnalyticWidth(height, diameter);
    CAPTURE(height, diameter, measured, expected);
    CHECK(std::fabs(measured - expected) / expected < 0.15);
    CHECK(measured > previous * 1.2);
    previous = measured;
  }
}

TEST_CASE("shadow filter: ssabss penumbra is view invariant, sspcss is not", "[shadow_filter]") {
  const float height = 0.5f, diameter = 8.0f;
  const CameraDesc headOn = Camera({0.0f, 0.45f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 25.0f);
  const float a = glm::radians(70.0f);
  const CameraDesc oblique = Camera(0.8f * glm::vec3(0.0f, std::cos(a), std::sin(a)), {0.0f, 0.0f, 0.0f},
                                    {0.0f, 1.0f, 0.0f}, 25.0f);
  const Rendered r0 = Render(SlabScene(headOn, height, diameter));
  const Rendered r1 = Render(SlabScene(oblique, height, diameter));
  const double abss0 = MeanEdgeWidth(r0, Filter(r0, ShadowFilter::kSsabss, 64));
  const double abss1 = MeanEdgeWidth(r1, Filter(r1, ShadowFilter::kSsabss, 64));
  const double pcss0 = MeanEdgeWidth(r0, Filter(r0, ShadowFilter::kSspcss, 64));
  const double pcss1 = MeanEdgeWidth(r1, Filter(r1, ShadowFilter::kSspcss, 64));
  const double abssChange = std::fabs(abss1 - abss0) / abss0, pcssChange = std::fabs(pcss1 - pcss0) / pcss0;
  CAPTURE(abss0, abss1, pcss0, pcss1, abssChange, pcssChange, AnalyticWidth(height, diameter));
  CHECK(abssChange < 0.15);
  CHECK(pcssChange > 2.0 * abssChange);
  CHECK(pcssChange > 0.5);
}

TEST_CASE("shadow filter: no bleeding across a depth discontinuity", "[shadow_filter]") {
  // A high slab over x < 0, the sun 30 degrees from vertical travelling +x: the ground is in umbra
  // up to x = 1.44 - 0.1. A lit box floats between the camera and that umbra; its left silhouette is
  // seen against umbra ground whose kernels (about 10 pixels) reach over it.
  const CameraDesc camera = Camera({1.0f, 2.3f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 45.0f);
  TestScene scene = MakeScene(camera, 256, 192);
  AddGround(scene.mesh, 6.0f);
  AddBox(scene.mesh, {-3.0f, 2.5f, -3.0f}, {0.0f, 2.52f, 3.0f});
  const glm::vec3 lo(0.8f, 1.2f, -0.2f), hi(1.2f, 1.5f, 0.2f);
  AddBox(scene.mesh, lo, hi);
  AddSun(scene, LightDirection(30.0f, 0.0f), 4.0f);
  const Rendered r = Render(std::move(scene));
  for (ShadowFilter filter : {ShadowFilter::kSsabss, ShadowFilter::kSspcss}) {
    const Plane<float> vis = Filter(r, filter);
    size_t boxTop = 0, umbraNearBox = 0;
    for (int y = 0; y < 192; ++y) {
      int boxLeft = -1;
      for (int x = 0; x < 256 && boxLeft < 0; ++x)
        if (!r.Background(x, y) && r.World(x, y).y > 1.0f) boxLeft = x;
      for (int x = 0; x < 256; ++x) {
        if (r.Background(x, y)) continue;
        const glm::vec3 p = r.World(x, y);
        if (std::fabs(p.y - hi.y) < 1e-3f) {
          ++boxTop;
          CHECK(!r.Hard(x, y));
          CHECK(vis.ConstRow(y)[x] == 1.0f);
        } else if (std::fabs(p.y) < 1e-3f && p.x < 1.1f && boxLeft >= 0 && x < boxLeft && x >= boxLeft - 12) {
          ++umbraNearBox;
          CHECK(r.Hard(x, y));
          CHECK(vis.ConstRow(y)[x] == 0.0f);
        }
      }
    }
    CHECK(boxTop > 1000);
    CHECK(umbraNearBox > 500);
  }
}

TEST_CASE("shadow filter: contact hardening", "[shadow_filter]") {
  // A zero-thickness wall at x = 0 standing on the ground, the sun 45 degrees from vertical travelling
  // +x, 4 degrees wide: the shadow's side edges (z = +-0.3) start at the wall's foot, where the blocker
  // distance goes to 0. Measured 1.5 cm from the foot: word 3's blocker distance there is the mean
  // over the PCSS search ring (a few cm of wall), not the 2 cm to the wall's edge, so the true contact
  // is not resolvable closer than that (docs/pipeline.md §Shadow map, known limits).
  const CameraDesc camera = Camera({0.3f, 0.9f, 0.0f}, {0.3f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 45.0f);
  TestScene scene = MakeScene(camera, 256, 192);
  AddGround(scene.mesh, 5.0f);
  AddQuad(scene.mesh, {0.0f, 0.0f, -0.3f}, {0.0f, 0.0f, 0.6f}, {0.0f, 0.6f, 0.0f});
  AddSun(scene, LightDirection(45.0f, 0.0f), 4.0f);
  const Rendered r = Render(std::move(scene));
  const Plane<float> vis = Filter(r, ShadowFilter::kSsabss);
  for (float side : {-0.3f, 0.3f}) {
    const glm::vec2 nearWall = r.Screen({0.015f, 0.0f, side});
    const glm::vec2 farWall = r.Screen({0.45f, 0.0f, side});
    const Edge contact = MeasureEdge(r, vis, int(nearWall.x), int(nearWall.y), 30);
    const Edge open = MeasureEdge(r, vis, int(farWall.x), int(farWall.y), 30);
    CAPTURE(side, contact.pixels, open.pixels);
    REQUIRE(contact.found);
    REQUIRE(open.found);
    CHECK(contact.pixels <= 2.0);
    CHECK(open.pixels > 4.0 * contact.pixels);
  }
}

bool ValidVisibility(const GBuffer& g, const Plane<float>& vis) {
  for (int y = 0; y < g.height(); ++y)
    for (int x = 0; x < g.width(); ++x) {
      const float v = vis.ConstRow(y)[x];
      if (!(v >= 0.0f && v <= 1.0f)) return false;
      if (!(UnpackDepth(g.word[2].ConstRow(y)[x]) < kBackgroundDepth) && v != 1.0f) return false;
    }
  return true;
}

TEST_CASE("shadow filter: robust to degenerate inputs", "[shadow_filter]") {
  // A hand-made G-buffer: normals facing the camera exactly, grazing and back-facing; blocker
  // distances 0, tiny, huge, FLT_MAX, +inf; random hard flags; background pixels.
  const int w = 37, h = 23;
  CameraDesc desc;
  const ViewProjection camera = MakePerspective(desc, w, h);
  GBuffer g = MakeGBuffer(w, h, NormalEncoding::kOct24);
  const float distances[] = {0.0f, 1e-30f, 0.3f, 1e30f, std::numeric_limits<float>::max(),
                             std::numeric_limits<float>::infinity()};
  uint32_t seed = 12345u;
  auto next = [&seed] { return seed = seed * 1664525u + 1013904223u; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint32_t k = next();
      if (k % 11 == 0) continue;  // background
      const float depth = 0.06f + float(k % 1000) * 0.01f;
      const glm::vec3 dir = camera.PixelRay(float(x) + 0.5f, float(y) + 0.5f).direction;
      glm::vec3 n;
      switch ((k >> 8) % 4) {
        case 0: n = -glm::normalize(dir); break;                           // faces the camera
        case 1: n = glm::vec3(1.0f, 0.0f, 0.0f); break;                    // grazing
        case 2: n = glm::normalize(glm::vec3(0.3f, 0.2f, -1.0f)); break;   // back-facing
        default: n = glm::normalize(glm::vec3(0.0f, 1.0f, 0.2f));
      }
      g.word[1].MutableRow(y)[x] = PackNormalRoughness(n, 0.5f, NormalEncoding::kOct24);
      g.word[2].MutableRow(y)[x] = PackDepth(depth);
      g.word[3].MutableRow(y)[x] = PackShadowTerm(((k >> 12) & 1) != 0, distances[(k >> 16) % 6]);
    }
  std::vector<PreparedLight> lights(4);
  lights[0].tanAngularRadius = 0.05f;
  lights[0].direction = {0.0f, -1.0f, 0.0f};
  lights[1].direction = {1.0f, 0.0f, 0.0f};  // grazing point light (no size)
  lights[2].isSpot = true;
  lights[2].radius = 0.2f;
  lights[2].position = {0.0f, 0.0f, -1.0f};  // among the receivers
  lights[3].isSpot = true;
  lights[3].radius = 0.0f;
  for (const PreparedLight& light : lights)
    for (ShadowFilter filter : {ShadowFilter::kHard, ShadowFilter::kSspcss, ShadowFilter::kSsabss})
      for (int maxRadius : {0, 3, 24, 200})
        for (int taps : {0, 1, 5}) {
          ShadowFilterParams params{filter, maxRadius, taps};
          ShadowFilterOutputs out;
          RunShadowFilter({g, camera, light}, params, out);
          CAPTURE(int(filter), maxRadius, taps, light.isSpot);
          CHECK(ValidVisibility(g, out.visibility));
        }

  // A rendered scene under a grazing sun (89 degrees from vertical) and a 20-degree sun whose
  // penumbrae exceed the radius clamp.
  const CameraDesc top = Camera({0.0f, 0.45f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 45.0f);
  for (float angle : {89.0f, 0.0f}) {
    TestScene scene = SlabScene(top, 0.5f, angle > 0.0f ? 2.0f : 20.0f);
    scene.directionalLights[0].direction = LightDirection(angle, 30.0f);
    const Rendered r = Render(std::move(scene));
    for (int maxRadius : {2, 24}) {
      const Plane<float> vis = Filter(r, ShadowFilter::kSsabss, maxRadius);
      CHECK(ValidVisibility(r.g.gbuffer, vis));
    }
  }
}

bool SameBits(const Plane<float>& a, const Plane<float>& b) {
  if (a.xsize() != b.xsize() || a.ysize() != b.ysize()) return false;
  for (size_t y = 0; y < a.ysize(); ++y)
    if (std::memcmp(a.ConstRow(y), b.ConstRow(y), a.xsize() * sizeof(float)) != 0) return false;
  return true;
}

TEST_CASE("shadow filter: same bits at 1, 2, 3 threads and with or without tile skipping", "[shadow_filter]") {
  const CameraDesc camera = Camera({0.6f, 1.2f, 1.6f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 45.0f);
  TestScene sun = SlabScene(camera, 0.5f, 6.0f);
  AddBox(sun.mesh, {0.3f, 0.0f, 0.2f}, {0.6f, 0.4f, 0.5f});
  sun.directionalLights[0].direction = LightDirection(35.0f, 60.0f);
  TestScene spot = sun;
  spot.directionalLights.clear();
  SpotLight light;
  light.position = {0.5f, 2.0f, 0.8f};
  light.direction = glm::normalize(glm::vec3(-0.5f, -2.0f, -0.8f));
  light.outerConeDegrees = 60.0f;
  light.radius = 0.15f;
  spot.spotLights.push_back(light);
  for (TestScene* scene : {&sun, &spot}) {
    const Rendered r = Render(*scene);
    for (ShadowFilter filter : {ShadowFilter::kSsabss, ShadowFilter::kSspcss})
      for (int taps : {0, 3}) {
        ShadowFilterParams params;
        params.filter = filter;
        params.taps = taps;
        const ShadowFilterInputs in{r.g.gbuffer, r.camera, r.light};
        ShadowFilterOutputs everyTile;
        const ShadowFilterStats all = RunShadowFilterEveryTile(in, params, everyTile);
        CHECK(all.tilesBlurred == all.tiles);
        for (int threads : {1, 2, 3}) {
          const ThreadLimit limit(threads);
          ShadowFilterOutputs out;
          const ShadowFilterStats stats = RunShadowFilter(in, params, out);
          CAPTURE(threads, int(filter), taps, stats.tiles, stats.tilesBlurred);
          CHECK(SameBits(out.visibility, everyTile.visibility));
          CHECK(stats.tilesBlurred > 0);
          CHECK(stats.tilesBlurred < stats.tiles);
        }
      }
  }
}

}  // namespace
}  // namespace ssgi
