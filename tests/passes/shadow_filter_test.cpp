#include "passes/shadow_filter.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "core/kernel_path.h"
#include "core/parallel.h"
#include "core/scene.h"
#include "passes/frame/frame.h"
#include "passes/gbuffer.h"
#include "passes/shadow_map.h"
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

  bool Background(int x, int y) const {
    return !(UnpackDepth(g.gbuffer.word[GBufferWord::kDepth].ConstRow(y)[x]) < kBackgroundDepth);
  }
  bool Hard(int x, int y) const { return UnpackHardShadow(g.gbuffer.word[GBufferWord::kShadowTerm].ConstRow(y)[x]); }
  glm::vec3 World(int x, int y) const { return test::WorldPosition(camera, g.gbuffer, x, y); }
  glm::vec2 Screen(glm::vec3 world) const {
    const glm::vec4 clip = camera.viewProjection * glm::vec4(world, 1.0f);
    return {(clip.x / clip.w * 0.5f + 0.5f) * float(camera.width),
            (0.5f - clip.y / clip.w * 0.5f) * float(camera.height)};
  }
};

// `light` indexes PrepareLights' order: directional lights, then spots.
Rendered Render(test::TestScene scene, size_t light = 0) {
  Rendered r;
  r.scene = std::move(scene);
  r.camera = MakePerspective(r.scene.camera, r.scene.width, r.scene.height);
  RunGBuffer({r.scene, r.camera}, {r.scene.normalEncoding}, r.g);
  ShadowMapOutputs out;
  RunShadowMap({r.scene, r.camera, r.g.gbuffer, light}, {}, out, r.g.gbuffer.word[GBufferWord::kShadowTerm]);
  r.light = PrepareLights(r.scene, r.camera.view)[light];
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
      if (!(UnpackDepth(g.word[GBufferWord::kDepth].ConstRow(y)[x]) < kBackgroundDepth) && v != 1.0f) return false;
    }
  return true;
}

// A hand-made G-buffer: normals facing the camera exactly, grazing and back-facing; blocker
// distances 0, tiny, huge, FLT_MAX, +inf; random hard flags; background pixels.
GBuffer DegenerateGBuffer(const ViewProjection& camera, NormalEncoding encoding) {
  GBuffer g = MakeGBuffer(camera.width, camera.height, encoding);
  const float distances[] = {0.0f, 1e-30f, 0.3f, 1e30f, std::numeric_limits<float>::max(),
                             std::numeric_limits<float>::infinity()};
  uint32_t seed = 12345u;
  auto next = [&seed] { return seed = seed * 1664525u + 1013904223u; };
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
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
      g.word[GBufferWord::kNormalRoughness].MutableRow(y)[x] = PackNormalRoughness(n, 0.5f, encoding);
      g.word[GBufferWord::kDepth].MutableRow(y)[x] = PackDepth(depth);
      g.word[GBufferWord::kShadowTerm].MutableRow(y)[x] =
          PackShadowTerm(((k >> 12) & 1) != 0, distances[(k >> 16) % 6]);
    }
  return g;
}

// A sized sun, a grazing point-like sun, a spot among the receivers and a spot of no size.
std::vector<PreparedLight> DegenerateLights() {
  std::vector<PreparedLight> lights(4);
  lights[0].tanAngularRadius = 0.05f;
  lights[0].direction = {0.0f, -1.0f, 0.0f};
  lights[1].direction = {1.0f, 0.0f, 0.0f};
  lights[2].isSpot = true;
  lights[2].radius = 0.2f;
  lights[2].position = {0.0f, 0.0f, -1.0f};
  lights[3].isSpot = true;
  lights[3].radius = 0.0f;
  return lights;
}

TEST_CASE("shadow filter: robust to degenerate inputs", "[shadow_filter]") {
  const ViewProjection camera = MakePerspective(CameraDesc{}, 37, 23);
  const GBuffer g = DegenerateGBuffer(camera, NormalEncoding::kOct24);
  for (const PreparedLight& light : DegenerateLights())
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

// The slab and a box seen obliquely under a sun (light 0) and a spot (light 1).
TestScene SunAndSpotScene(int width, int height) {
  const CameraDesc camera = Camera({0.6f, 1.2f, 1.6f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 45.0f);
  TestScene scene = SlabScene(camera, 0.5f, 6.0f);
  scene.width = width;
  scene.height = height;
  AddBox(scene.mesh, {0.3f, 0.0f, 0.2f}, {0.6f, 0.4f, 0.5f});
  scene.directionalLights[0].direction = LightDirection(35.0f, 60.0f);
  SpotLight spot;
  spot.position = {0.5f, 2.0f, 0.8f};
  spot.direction = glm::normalize(glm::vec3(-0.5f, -2.0f, -0.8f));
  spot.outerConeDegrees = 60.0f;
  spot.radius = 0.15f;
  scene.spotLights.push_back(spot);
  return scene;
}

TEST_CASE("shadow filter: same bits at 1, 2, 3 threads and with or without tile skipping", "[shadow_filter]") {
  for (size_t light : {size_t(0), size_t(1)}) {
    const Rendered r = Render(SunAndSpotScene(256, 192), light);
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
          CHECK(test::SameBytes(out.visibility, everyTile.visibility));
          CHECK(stats.tilesBlurred > 0);
          CHECK(stats.tilesBlurred < stats.tiles);
        }
      }
  }
}

// ---- The SIMD twins against their scalar definitions, bit for bit on every target (docs/design.md §11)

bool SameFloats(const float* a, const float* b, size_t count) {
  return test::FirstDifferentBits(a, b, count) == count;
}

bool SameSummaries(const std::vector<ShadowFilterTileSummary>& a, const std::vector<ShadowFilterTileSummary>& b) {
  for (size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a[i].maxRadius, &b[i].maxRadius, sizeof(float)) != 0 ||
        a[i].geometryPixels != b[i].geometryPixels || a[i].litPixels != b[i].litPixels)
      return false;
  return true;
}

constexpr int kTilePixels = kShadowFilterTileSize * kShadowFilterTileSize;

// The set-up's arrays for a run of `count` pixels, with the margins ShadowFilterImage asks for,
// filled with a marker the kernels must overwrite (and leave in the margins).
constexpr size_t kMargin = kShadowFilterTileSize;
struct SetupArrays {
  size_t count;
  std::vector<float> storage;
  ShadowFilterTexels texels;
  ShadowFilterKernels kernels;

  explicit SetupArrays(size_t pixels) : count(pixels), storage(kMargin + 11 * pixels + kMargin, -7.0f) {
    float* a = storage.data() + kMargin;
    texels = {a, a + count, a + 2 * count, a + 3 * count, a + 4 * count, a + 5 * count, a + 6 * count};
    kernels = {a + 7 * count, a + 8 * count, a + 9 * count, a + 10 * count};
  }
};

// Every tile of a G-buffer set up by the scalar kernel (slot = tile), the input of the passes' twins.
struct SetUpImage {
  std::vector<int32_t> slots;
  SetupArrays arrays;
  ShadowFilterImage image;

  SetUpImage(const ShadowFilterSetupContext& context, const GBuffer& g)
      : arrays(size_t((g.width() + kShadowFilterTileSize - 1) / kShadowFilterTileSize) *
               size_t((g.height() + kShadowFilterTileSize - 1) / kShadowFilterTileSize) * kTilePixels) {
    const int tilesX = (g.width() + kShadowFilterTileSize - 1) / kShadowFilterTileSize;
    slots.resize(arrays.count / kTilePixels);
    for (size_t tile = 0; tile < slots.size(); ++tile) slots[tile] = int32_t(tile);
    image = {arrays.texels, arrays.kernels, slots.data(), g.width(), g.height(), tilesX};
    for (int y = 0; y < g.height(); ++y)
      for (int x = 0; x < g.width(); ++x) {
        const size_t i = image.Index(x, y);
        const ShadowFilterKernels kernels = arrays.kernels + i;
        ShadowFilterSetupRowScalar(
            context, g.word[GBufferWord::kNormalRoughness].ConstRow(y) + x, g.word[GBufferWord::kDepth].ConstRow(y) + x,
            g.word[GBufferWord::kShadowTerm].ConstRow(y) + x, x, y, 1, arrays.texels + i, &kernels);
      }
  }
};

// The runs of a row the twins are checked on: the whole row, each tile's part, and every length
// from 1 to a few vectors from a few starts.
std::vector<std::pair<int, int>> Runs(int width) {
  std::vector<std::pair<int, int>> runs{{0, width}};
  for (int x = 0; x < width; x += kShadowFilterTileSize)
    runs.push_back({x, std::min(width, x + kShadowFilterTileSize)});
  for (int x : {0, 3, 17})
    for (int count = 1; count <= 53 && x + count <= width; ++count) runs.push_back({x, x + count});
  return runs;
}

struct TwinInputs {
  std::string name;
  ViewProjection camera;
  GBuffer gbuffer;
  std::vector<PreparedLight> lights;
};

// The degenerate G-buffer in both normal encodings with its lights, and a rendered scene with real
// penumbrae under a sun and a spot (odd sizes, so edge tiles are partial).
std::vector<TwinInputs> TwinInputSets() {
  std::vector<TwinInputs> sets;
  for (NormalEncoding encoding : {NormalEncoding::kOct24, NormalEncoding::kXyz8}) {
    const ViewProjection camera = MakePerspective(CameraDesc{}, 75, 37);
    sets.push_back({"degenerate", camera, DegenerateGBuffer(camera, encoding), DegenerateLights()});
  }
  for (size_t light : {size_t(0), size_t(1)}) {
    Rendered r = Render(SunAndSpotScene(91, 53), light);
    sets.push_back({light == 0 ? "sun" : "spot", r.camera, std::move(r.g.gbuffer), {r.light}});
  }
  return sets;
}

TEST_CASE("shadow filter: the SIMD set-up kernels equal their scalar definitions on every target",
          "[shadow_filter][simd]") {
  for (const TwinInputs& set : TwinInputSets()) {
    const GBuffer& g = set.gbuffer;
    const int width = g.width(), tilesX = (width + kShadowFilterTileSize - 1) / kShadowFilterTileSize;
    const PixelRayTables rays = MakePixelRayTables(set.camera, size_t(width), size_t(g.height()));
    for (const PreparedLight& light : set.lights)
      for (ShadowFilter filter : {ShadowFilter::kHard, ShadowFilter::kSspcss, ShadowFilter::kSsabss})
        for (int maxRadius : {0, 3, 24, 200}) {
          const ShadowFilterSetupContext context = MakeShadowFilterSetupContext(
              {g, set.camera, light}, ShadowFilterParams{filter, maxRadius, 0}, rays);
          const size_t targets = test::ForEachSimdTarget([&](const char* target) {
            for (int y = 0; y < g.height(); ++y) {
              // Every run on one row, the whole row on the others.
              const std::vector<std::pair<int, int>> runs =
                  y == 17 ? Runs(width) : std::vector<std::pair<int, int>>{{0, width}};
              for (const auto& [x0, x1] : runs) {
                const int count = x1 - x0;
                const uint32_t* w1 = g.word[GBufferWord::kNormalRoughness].ConstRow(y) + x0;
                const uint32_t* w2 = g.word[GBufferWord::kDepth].ConstRow(y) + x0;
                const uint32_t* w3 = g.word[GBufferWord::kShadowTerm].ConstRow(y) + x0;
                CAPTURE(set.name, target, light.isSpot, int(filter), maxRadius, y, x0, count);
                std::vector<float> hardScalar(static_cast<size_t>(count), -7.0f), hardSimd = hardScalar;
                std::vector<ShadowFilterTileSummary> tilesScalar(static_cast<size_t>(tilesX)), tilesSimd = tilesScalar;
                ShadowFilterPenumbraRowScalar(context, w2, w3, x0, y, count, hardScalar.data(), tilesScalar.data());
                ShadowFilterPenumbraRowSimd(context, w2, w3, x0, y, count, hardSimd.data(), tilesSimd.data());
                REQUIRE(SameFloats(hardScalar.data(), hardSimd.data(), size_t(count)));
                REQUIRE(SameSummaries(tilesScalar, tilesSimd));
                for (const bool withKernels : {true, false}) {
                  SetupArrays scalar(static_cast<size_t>(count)), simd(static_cast<size_t>(count));
                  ShadowFilterSetupRowScalar(context, w1, w2, w3, x0, y, count, scalar.texels,
                                             withKernels ? &scalar.kernels : nullptr);
                  ShadowFilterSetupRowSimd(context, w1, w2, w3, x0, y, count, simd.texels,
                                           withKernels ? &simd.kernels : nullptr);
                  CAPTURE(withKernels);
                  // The markers too: nothing written outside the run, no kernels without `kernels`.
                  REQUIRE(SameFloats(scalar.storage.data(), simd.storage.data(), scalar.storage.size()));
                }
              }
            }
          });
          CHECK(targets >= 1);
        }
  }
}

TEST_CASE("shadow filter: the SIMD passes equal their scalar definitions on every target", "[shadow_filter][simd]") {
  for (const TwinInputs& set : TwinInputSets()) {
    const GBuffer& g = set.gbuffer;
    const int width = g.width(), height = g.height();
    const PixelRayTables rays = MakePixelRayTables(set.camera, size_t(width), size_t(height));
    for (const PreparedLight& light : set.lights)
      for (ShadowFilter filter : {ShadowFilter::kSspcss, ShadowFilter::kSsabss})
        for (const auto& [maxRadius, taps] : {std::pair{3, 0}, {24, 0}, {24, 1}, {3, 5}}) {
          const ShadowFilterSetupContext context = MakeShadowFilterSetupContext(
              {g, set.camera, light}, ShadowFilterParams{filter, maxRadius, taps}, rays);
          const SetUpImage setUp(context, g);
          const ShadowFilterImage& image = setUp.image;
          // Pass 2 blurs pass 1's values; any values in [0, 1] would do.
          std::vector<float> majorStorage(kMargin + setUp.arrays.count + kMargin);
          float* major = majorStorage.data() + kMargin;
          for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
              ShadowFilterMajorRowScalar(image, image.texels.hard, taps, y, x, x + 1, major + image.Index(x, y));
          const size_t targets = test::ForEachSimdTarget([&](const char* target) {
            for (int y = 0; y < height; ++y) {
              const std::vector<std::pair<int, int>> runs =
                  y == 17 ? Runs(width) : std::vector<std::pair<int, int>>{{0, width}};
              for (const auto& [x0, x1] : runs) {
                const size_t count = size_t(x1 - x0);
                CAPTURE(set.name, target, light.isSpot, int(filter), maxRadius, taps, y, x0, count);
                std::vector<float> scalar(count + 1, -7.0f), simd = scalar;
                ShadowFilterMajorRowScalar(image, image.texels.hard, taps, y, x0, x1, scalar.data());
                ShadowFilterMajorRowSimd(image, image.texels.hard, taps, y, x0, x1, simd.data());
                REQUIRE(SameFloats(scalar.data(), simd.data(), count + 1));
                ShadowFilterMinorRowScalar(image, major, taps, y, x0, x1, scalar.data());
                ShadowFilterMinorRowSimd(image, major, taps, y, x0, x1, simd.data());
                REQUIRE(SameFloats(scalar.data(), simd.data(), count + 1));
              }
            }
          });
          CHECK(targets >= 1);
        }
  }
}

TEST_CASE("shadow filter: the SIMD kernel path gives the scalar path's bytes on every target",
          "[shadow_filter][simd]") {
  // The default scene's real buffers, frames at its own size and at odd sizes; with and without
  // tile skipping, as the small images have few penumbrae to blur.
  const test::DefaultScene scene = test::LoadDefaultScene();
  test::ForEachDefaultSceneFrame([&scene](const Frame& frame) {
    REQUIRE(frame.shadowMap);
    const PreparedLight light =
        PrepareLights(scene.scene, frame.view.view)[ShadowCastingLights(scene.scene).front()];
    const ShadowFilterInputs in{frame.gbuffer.gbuffer, frame.view, light};
    const auto same = [](const Plane<float>& a, const Plane<float>& b) { return test::SameBytes(a, b); };
    size_t blurred = 0;
    for (ShadowFilter filter : {ShadowFilter::kSsabss, ShadowFilter::kSspcss})
      for (int taps : {0, 3}) {
        ShadowFilterParams params = scene.config.shadowFilter;
        params.filter = filter;
        params.taps = taps;
        CAPTURE(frame.view.width, frame.view.height, int(filter), taps);
        const auto run = [&](KernelPath kernels) {
          ShadowFilterOutputs out;
          blurred += RunShadowFilter(in, params, out, kernels).tilesBlurred;
          return std::move(out.visibility);
        };
        const auto runEveryTile = [&](KernelPath kernels) {
          ShadowFilterOutputs out;
          RunShadowFilterEveryTile(in, params, out, kernels);
          return std::move(out.visibility);
        };
        CHECK(test::TargetsWhereKernelPathsDiffer(run, same) == "");
        CHECK(test::TargetsWhereKernelPathsDiffer(runEveryTile, same) == "");
      }
    if (frame.view.width > 1000) CHECK(blurred > 0);
    // The frame's own filter ran the default path.
    ShadowFilterOutputs scalar;
    RunShadowFilter(in, scene.config.shadowFilter, scalar, KernelPath::kScalar);
    CHECK(test::SameBytes(scalar.visibility, frame.shadowVisibility.visibility));
  });
}

}  // namespace
}  // namespace ssgi
