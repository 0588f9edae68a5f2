#include "passes/ssr_trace.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "core/parallel.h"
#include "passes/gbuffer.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

struct Traced {
  GBuffer gbuffer;
  ViewProjection view;
  HiZ hiz;
  SsrTraceOutputs out;
  SsrTraceStats stats;
};

constexpr glm::vec3 kBoxLo{-0.8f, 0.0f, -0.4f};
constexpr glm::vec3 kBoxHi{0.8f, 1.0f, 0.4f};

// A mirror floor (roughness 0) with a box standing on it, seen from above and in front.
Traced TraceMirrorFloor(int width, int height, NormalEncoding encoding, const SsrTraceParams& params = {}) {
  CameraDesc camera;
  camera.position = {0.0f, 1.2f, 4.0f};
  camera.target = {0.0f, 0.4f, 0.0f};
  Scene scene = test::MakeScene(camera, width, height);
  scene.materials[0].roughness = 0.0f;
  test::AddGround(scene.mesh, 10.0f);
  test::AddBox(scene.mesh, kBoxLo, kBoxHi);
  Traced t;
  t.view = MakePerspective(camera, width, height);
  GBufferOutputs g;
  RunGBuffer({scene, t.view}, {encoding}, g);
  t.gbuffer = std::move(g.gbuffer);
  RunHiZ(t.gbuffer.word[GBufferWord::kDepth], t.hiz);
  t.stats = RunSsrTrace({t.gbuffer, t.view, t.hiz}, params, t.out);
  return t;
}

// Every output pixel is either "no hit" (-1, -1, 0) or a hit inside the image with confidence in
// (0, 1]; never NaN.
void CheckOutputsWellFormed(const SsrTraceOutputs& out) {
  const size_t width = out.hitX.xsize();
  const size_t height = out.hitX.ysize();
  size_t bad = 0;
  for (size_t y = 0; y < height; ++y) {
    for (size_t x = 0; x < width; ++x) {
      const float hx = out.hitX.ConstRow(y)[x];
      const float hy = out.hitY.ConstRow(y)[x];
      const float c = out.confidence.ConstRow(y)[x];
      const bool noHit = hx == -1.0f && hy == -1.0f && c == 0.0f;
      const bool hit = hx >= 0.0f && hx < float(width) && hy >= 0.0f && hy < float(height) && c > 0.0f &&
                       c <= 1.0f;
      if (!noHit && !hit) ++bad;
    }
  }
  CHECK(bad == 0);
}

constexpr int kMirrorWidth = 256;
constexpr int kMirrorHeight = 192;

// Checks t's hits against the analytic mirror point on the box's front face.
void CheckMirrorFloorHits(const Traced& t) {
  constexpr int kWidth = kMirrorWidth;
  constexpr int kHeight = kMirrorHeight;
  const glm::vec3 eye{0.0f, 1.2f, 4.0f};
  constexpr float kMargin = 0.03f;  // metres kept clear of the face's edges (ambiguous pixels)

  std::vector<float> errors;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::optional<glm::vec3> q =
          test::MirrorPointOnBoxFront(eye, test::WorldPosition(t.view, t.gbuffer, x, y), kBoxLo, kBoxHi, kMargin);
      if (!q) continue;
      const glm::vec4 clip = t.view.viewProjection * glm::vec4(*q, 1.0f);
      const float sx = (clip.x / clip.w * 0.5f + 0.5f) * float(kWidth);
      const float sy = (0.5f - clip.y / clip.w * 0.5f) * float(kHeight);
      const float hx = t.out.hitX.ConstRow(size_t(y))[x];
      const float hy = t.out.hitY.ConstRow(size_t(y))[x];
      errors.push_back(hx < 0.0f ? std::numeric_limits<float>::infinity() : std::hypot(hx - sx, hy - sy));
    }
  }
  REQUIRE(errors.size() > 500);
  const size_t within = size_t(std::count_if(errors.begin(), errors.end(), [](float e) { return e <= 1.0f; }));
  std::sort(errors.begin(), errors.end());
  const float median = errors[errors.size() / 2];
  const double fraction = double(within) / double(errors.size());
  std::printf("[ssr] mirror floor %dx%d: %zu analytic pixels, %.2f%% within 1 px, median error %.3f px; "
              "%zu rays, %.2f mean iterations, %zu tiles\n",
              kWidth, kHeight, errors.size(), 100.0 * fraction, double(median), t.stats.rays,
              t.stats.meanIterations, t.stats.tilesTraced);
  CHECK(fraction >= 0.95);
  CHECK(median <= 0.5f);
  CheckOutputsWellFormed(t.out);
}

TEST_CASE("SSR hits on a mirror floor match the analytic reflection of the box's front face", "[ssr]") {
  CheckMirrorFloorHits(TraceMirrorFloor(kMirrorWidth, kMirrorHeight, NormalEncoding::kOct24));
}

// The max pyramid is conservative at every level, so where the march starts changes its cost, never
// what it finds.
TEST_CASE("SSR hits stay on the analytic mirror point at every Hi-Z start level", "[ssr]") {
  double previousIterations = 0;
  for (const int startLevel : {0, 2, 4, 7, 30}) {
    CAPTURE(startLevel);
    SsrTraceParams params;
    params.startLevel = startLevel;
    const Traced t = TraceMirrorFloor(kMirrorWidth, kMirrorHeight, NormalEncoding::kOct24, params);
    CheckMirrorFloorHits(t);
    CHECK(t.stats.meanIterations != previousIterations);
    previousIterations = t.stats.meanIterations;
  }
}

// A Hi-Z over a width x height depth image given by depth(x, y) in metres.
HiZ MakeHiZ(int width, int height, const std::function<float(int, int)>& depth) {
  Plane<uint32_t> word = MakePlane<uint32_t>(size_t(width), size_t(height), 0u);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) word.MutableRow(size_t(y))[x] = PackDepth(depth(x, y));
  HiZ hiz;
  RunHiZ(word, hiz);
  return hiz;
}

TEST_CASE("SSR march: axis-aligned rays find a wall and stop, degenerate rays terminate", "[ssr]") {
  constexpr int kWidth = 64;
  constexpr int kHeight = 48;
  constexpr int kCap = 64;
  // A far floor at 10 m with near walls at 2 m: column 40, column 5, row 30, row 4.
  const HiZ hiz = MakeHiZ(kWidth, kHeight, [](int x, int y) {
    return x == 40 || x == 5 || y == 30 || y == 4 ? 2.0f : 10.0f;
  });
  struct Case {
    glm::vec3 origin;
    glm::vec3 end;
    int wallX;  // expected hit column or -1
    int wallY;  // expected hit row or -1
  };
  const float iz = 1.0f / 5.0f;  // the ray at 5 m: in front of the floor, behind the walls
  const Case cases[] = {
      {{10.5f, 20.5f, iz}, {500.0f, 20.5f, iz}, 40, 20},   // +x
      {{30.5f, 20.5f, iz}, {-500.0f, 20.5f, iz}, 5, 20},   // -x
      {{20.5f, 10.5f, iz}, {20.5f, 500.0f, iz}, 20, 30},   // +y
      {{20.5f, 20.5f, iz}, {20.5f, -500.0f, iz}, 20, 4},   // -y
      {{41.0f, 20.0f, iz}, {41.0f, -500.0f, iz}, 41, 4},   // -y from a pixel corner
  };
  for (const Case& c : cases) {
    const HiZMarch m = MarchHiZ(hiz, {c.origin, c.end}, kCap, 1);
    INFO("origin " << c.origin.x << ", " << c.origin.y << " iterations " << m.iterations);
    CHECK(m.hit);
    CHECK(m.iterations <= kCap);
    CHECK(int(std::floor(m.position.x)) == c.wallX);
    CHECK(int(std::floor(m.position.y)) == c.wallY);
  }

  // No walls: axis-aligned, diagonal, purely-depth and zero-length rays, from corners and edges, in
  // both depth directions, all end (miss) within the cap with finite positions.
  const HiZ open = MakeHiZ(kWidth, kHeight, [](int, int) { return 10.0f; });
  const glm::vec3 origins[] = {{0.0f, 0.0f, iz}, {63.99f, 47.99f, iz}, {0.5f, 24.0f, iz}, {32.0f, 24.0f, iz}};
  const glm::vec3 offsets[] = {{1e4f, 0, 0}, {-1e4f, 0, 0}, {0, 1e4f, 0}, {0, -1e4f, 0}, {1e4f, 1e4f, 0},
                               {-3.0f, 7.0f, 0}, {0, 0, 1.0f}, {0, 0, -0.1f}, {0, 0, 0}, {1e-30f, -1e-30f, 0}};
  for (const glm::vec3& o : origins) {
    for (const glm::vec3& d : offsets) {
      for (int cap : {1, 7, kCap}) {
        const HiZMarch m = MarchHiZ(open, {o, o + d}, cap, 1);
        CHECK_FALSE(m.hit);
        CHECK(m.iterations <= cap);
        CHECK(std::isfinite(m.position.x));
        CHECK(std::isfinite(m.position.y));
        CHECK(std::isfinite(m.position.z));
      }
    }
  }
}

// A hand-built G-buffer: random depths, random unit normals over the whole sphere (so rays go toward
// the camera, off screen, along the axes, from every edge pixel), some background, roughness 0 or,
// with randomRoughness, any code (so some pixels are past the cut-off).
GBuffer RandomGBuffer(int width, int height, NormalEncoding encoding, uint32_t seed, bool randomRoughness = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> depth(0.5f, 20.0f);
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  std::uniform_int_distribution<int> background(0, 9);
  std::uniform_int_distribution<int> roughness(0, 255);
  GBuffer g = MakeGBuffer(width, height, encoding);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (background(rng) == 0) continue;
      glm::vec3 n{gauss(rng), gauss(rng), gauss(rng)};
      if (x % 7 == 0) n = {0.0f, 0.0f, 1.0f};  // facing the camera: the ray returns toward it
      if (x % 11 == 0) n = {0.0f, 1.0f, 0.2f};
      const float r = randomRoughness ? float(roughness(rng)) / 255.0f : 0.0f;
      g.word[GBufferWord::kNormalRoughness].MutableRow(size_t(y))[x] =
          PackNormalRoughness(glm::normalize(n), r, encoding);
      g.word[GBufferWord::kDepth].MutableRow(size_t(y))[x] = PackDepth(depth(rng));
    }
  }
  return g;
}

// Surfaces whose neighbouring pixels are near the shared-ray tolerances, either side: normals that
// turn slowly with noise of about the normal tolerance, depths with jumps of about the depth
// tolerance, random roughness, some background.
GBuffer SmoothGBuffer(int width, int height, NormalEncoding encoding, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> gauss(0.0f, 0.04f);
  std::uniform_real_distribution<float> jump(-0.08f, 0.08f);
  std::uniform_int_distribution<int> background(0, 19);
  std::uniform_int_distribution<int> roughness(0, 200);
  GBuffer g = MakeGBuffer(width, height, encoding);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (background(rng) == 0) continue;
      const glm::vec3 n{std::sin(float(x) * 0.1f) + gauss(rng), std::cos(float(y) * 0.13f) + gauss(rng), 1.5f};
      g.word[GBufferWord::kNormalRoughness].MutableRow(size_t(y))[x] =
          PackNormalRoughness(glm::normalize(n), float(roughness(rng)) / 255.0f, encoding);
      const float d = (3.0f + 0.05f * float(x) + 0.03f * float(y)) * (1.0f + ((x + y) % 3 == 0 ? jump(rng) : 0.0f));
      g.word[GBufferWord::kDepth].MutableRow(size_t(y))[x] = PackDepth(d);
    }
  }
  return g;
}

TEST_CASE("SSR trace on random G-buffers terminates within the cap with well-formed outputs", "[ssr]") {
  for (const NormalEncoding encoding : {NormalEncoding::kOct24, NormalEncoding::kXyz8}) {
    for (const auto& [width, height] : {std::pair{67, 45}, std::pair{1, 1}, std::pair{1, 9}, std::pair{33, 2}}) {
      const GBuffer g = RandomGBuffer(width, height, encoding, uint32_t(width * 100 + height));
      CameraDesc camera;
      const ViewProjection view = MakePerspective(camera, width, height);
      HiZ hiz;
      RunHiZ(g.word[GBufferWord::kDepth], hiz);
      for (int cap : {1, 64}) {
        SsrTraceParams params;
        params.maxIterations = cap;
        SsrTraceOutputs out;
        const SsrTraceStats stats = RunSsrTrace({g, view, hiz}, params, out);
        INFO(width << "x" << height << " cap " << cap);
        CHECK(stats.meanIterations <= double(cap));
        CheckOutputsWellFormed(out);
        if (width == 67) CHECK(stats.rays > 1000);
      }
    }
  }
}

void CheckSame(const Plane<float>& a, const Plane<float>& b) {
  REQUIRE(a.xsize() == b.xsize());
  REQUIRE(a.ysize() == b.ysize());
  for (size_t y = 0; y < a.ysize(); ++y)
    CHECK(std::memcmp(a.ConstRow(y), b.ConstRow(y), a.xsize() * sizeof(float)) == 0);
}

TEST_CASE("SSR trace outputs are byte-identical at 1, 2 and 3 threads", "[ssr]") {
  const GBuffer g = RandomGBuffer(131, 77, NormalEncoding::kOct24, 7);
  const ViewProjection view = MakePerspective(CameraDesc{}, 131, 77);
  HiZ hiz;
  RunHiZ(g.word[GBufferWord::kDepth], hiz);
  std::vector<Traced> floors;
  std::vector<SsrTraceOutputs> randoms;
  for (int threads : {1, 2, 3}) {
    const ThreadLimit limit(threads);
    floors.push_back(TraceMirrorFloor(160, 120, NormalEncoding::kOct24));
    SsrTraceOutputs out;
    RunSsrTrace({g, view, hiz}, {}, out);
    randoms.push_back(std::move(out));
  }
  for (size_t i = 1; i < 3; ++i) {
    CheckSame(floors[0].out.hitX, floors[i].out.hitX);
    CheckSame(floors[0].out.hitY, floors[i].out.hitY);
    CheckSame(floors[0].out.confidence, floors[i].out.confidence);
    CheckSame(randoms[0].hitX, randoms[i].hitX);
    CheckSame(randoms[0].hitY, randoms[i].hitY);
    CheckSame(randoms[0].confidence, randoms[i].confidence);
  }
}

// Oct24 codes whose decoded normal has an exact 0 in x (v = 4095) or y (u = 0 or 4095): at the
// centre column (row) of an odd-sized image, where the view ray's x (y) is exactly 0 too, the
// reflected ray stays in that column (row), an exactly vertical (horizontal) march with a zero
// direction component. Random depths, so the rays meet walls and pass behind them.
GBuffer AxisAlignedGBuffer(int width, int height, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> depth(0.5f, 20.0f);
  std::uniform_int_distribution<uint32_t> code(0, 4095);
  GBuffer g = MakeGBuffer(width, height, NormalEncoding::kOct24);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const uint32_t u = code(rng), v = code(rng);
      const uint32_t word = (x + y) % 3 == 0 ? u | 4095u << 12 : (x + y) % 3 == 1 ? 4095u | v << 12 : v << 12;
      g.word[GBufferWord::kNormalRoughness].MutableRow(size_t(y))[x] = word;
      g.word[GBufferWord::kDepth].MutableRow(size_t(y))[x] = PackDepth(depth(rng));
    }
  }
  return g;
}

SsrTraceOutputs UntouchedOutputs(int width, int height) {
  constexpr float kUntouched = -7.0f;
  SsrTraceOutputs out;
  for (Plane<float>* plane : {&out.hitX, &out.hitY, &out.confidence, &out.iterations})
    *plane = MakePlane<float>(size_t(width), size_t(height), kUntouched);
  return out;
}

// SsrTraceTileSimd against SsrTraceTileScalar on every compiled and supported target: the 32x32
// tiles of the image, and tiles of every width from 1 to 32 at corners on the 4x4 grid, with heights
// from 1 to 32. Same bits in the tile, nothing written outside it, same counts.
void CheckTileTwins(const GBuffer& g, const ViewProjection& view, const HiZ& hiz, const SsrTraceParams& params) {
  const SsrTraceInputs in{g, view, hiz};
  const int width = g.width(), height = g.height();
  std::vector<SsrTraceTile> tiles;
  for (int y = 0; y < height; y += 32)
    for (int x = 0; x < width; x += 32) tiles.push_back({x, y, std::min(x + 32, width), std::min(y + 32, height)});
  for (int w = 1; w <= std::min(width, 32); ++w) {
    const int x0 = (w * 4) % width & ~3, y0 = (w * 8) % height & ~3;
    const int h = 1 + (w * 7) % 32;
    tiles.push_back({x0, y0, std::min(x0 + w, width), std::min(y0 + h, height)});
  }
  const size_t targets = test::ForEachSimdTarget([&](const char* target) {
    for (const SsrTraceTile& tile : tiles) {
      SsrTraceOutputs expected = UntouchedOutputs(width, height), actual = UntouchedOutputs(width, height);
      SsrTraceCounts expectedCounts, counts;
      SsrTraceTileScalar(in, params, tile, expected, expectedCounts);
      SsrTraceTileSimd(in, params, tile, actual, counts);
      CAPTURE(target, tile.x0, tile.y0, tile.x1, tile.y1, params.maxIterations, params.startLevel, params.quadRoughness,
              params.blockRoughness);
      REQUIRE(test::SameBytes(actual.hitX, expected.hitX));
      REQUIRE(test::SameBytes(actual.hitY, expected.hitY));
      REQUIRE(test::SameBytes(actual.confidence, expected.confidence));
      REQUIRE(test::SameBytes(actual.iterations, expected.iterations));
      REQUIRE(counts.rays == expectedCounts.rays);
      REQUIRE(counts.iterations == expectedCounts.iterations);
    }
  });
  CHECK(targets >= 2);
}

TEST_CASE("SSR trace: the SIMD tile kernel equals the scalar one on every target", "[ssr][simd]") {
  SECTION("mirror floor, every Hi-Z start level, iteration caps 1, 7 and 64") {
    const Traced t = TraceMirrorFloor(kMirrorWidth, kMirrorHeight, NormalEncoding::kOct24);
    const int levels = int(t.hiz.levels.size());
    for (int startLevel = 0; startLevel <= levels; ++startLevel) {
      for (const int cap : {1, 7, 64}) {
        SsrTraceParams params;
        params.startLevel = startLevel;
        params.maxIterations = cap;
        CheckTileTwins(t.gbuffer, t.view, t.hiz, params);
      }
    }
  }
  SECTION("mirror floor and random G-buffers with shared rays") {
    const Traced t = TraceMirrorFloor(kMirrorWidth, kMirrorHeight, NormalEncoding::kOct24);
    for (const auto& [quad, block] :
         {std::pair{0.0f, 0.0f}, std::pair{0.0f, 1.0f}, std::pair{1.0f, 0.0f}, std::pair{0.3f, 0.5f}}) {
      SsrTraceParams params;
      params.quadRoughness = quad;
      params.blockRoughness = block;
      CheckTileTwins(t.gbuffer, t.view, t.hiz, params);
      for (const NormalEncoding encoding : {NormalEncoding::kOct24, NormalEncoding::kXyz8}) {
        const GBuffer g = SmoothGBuffer(70, 45, encoding, 5);
        const ViewProjection view = MakePerspective(CameraDesc{}, 70, 45);
        HiZ hiz;
        RunHiZ(g.word[GBufferWord::kDepth], hiz);
        CheckTileTwins(g, view, hiz, params);
      }
    }
  }
  SECTION("random G-buffers: rays toward the camera, off screen, from edges; rough pixels; fades") {
    for (const NormalEncoding encoding : {NormalEncoding::kOct24, NormalEncoding::kXyz8}) {
      for (const auto& [width, height] : {std::pair{67, 45}, std::pair{1, 1}, std::pair{1, 9}, std::pair{33, 2}}) {
        const GBuffer g = RandomGBuffer(width, height, encoding, uint32_t(width * 100 + height), true);
        const ViewProjection view = MakePerspective(CameraDesc{}, width, height);
        HiZ hiz;
        RunHiZ(g.word[GBufferWord::kDepth], hiz);
        for (int startLevel = 0; startLevel <= int(hiz.levels.size()); ++startLevel) {
          for (const int cap : {1, 64}) {
            SsrTraceParams params;
            params.startLevel = startLevel;
            params.maxIterations = cap;
            CheckTileTwins(g, view, hiz, params);
          }
        }
        SsrTraceParams other;
        other.edgeFade = 0.0f;
        other.thickness = 0.5f;
        other.towardCameraFade = 1.0f;
        other.roughnessCutoff = 1.0f;
        CheckTileTwins(g, view, hiz, other);
      }
    }
  }
  SECTION("axis-aligned rays") {
    const GBuffer g = AxisAlignedGBuffer(65, 49, 3);
    const ViewProjection view = MakePerspective(CameraDesc{}, 65, 49);
    HiZ hiz;
    RunHiZ(g.word[GBufferWord::kDepth], hiz);
    // The centre column and row do march along an axis: some of their rays are traced.
    SsrTraceCounts column, row;
    SsrTraceOutputs scratch = UntouchedOutputs(65, 49);
    const SsrTraceInputs in{g, view, hiz};
    SsrTraceTileScalar(in, {}, {32, 0, 33, 49}, scratch, column);
    SsrTraceTileScalar(in, {}, {0, 24, 65, 25}, scratch, row);
    CHECK(column.rays > 5);
    CHECK(row.rays > 5);
    for (int startLevel : {0, 1, 3}) {
      for (const int cap : {1, 64}) {
        SsrTraceParams params;
        params.startLevel = startLevel;
        params.maxIterations = cap;
        CheckTileTwins(g, view, hiz, params);
      }
    }
  }
}

TEST_CASE("SSR trace: the SIMD pass gives the scalar pass's bytes on every target, default scene", "[ssr][simd]") {
  test::ForEachDefaultSceneFrame([](const Frame& frame) {
    CAPTURE(frame.view.width, frame.view.height);
    REQUIRE(frame.reflections);
    const SsrTraceInputs in{frame.gbuffer.gbuffer, frame.view, frame.hiz};
    SsrTraceOutputs expected;
    const SsrTraceStats expectedStats = RunSsrTrace(in, {}, expected, KernelPath::kScalar);
    if (frame.view.width > 1) CHECK(expectedStats.rays > size_t(frame.view.width));
    const size_t targets = test::ForEachSimdTarget([&](const char* target) {
      CAPTURE(target);
      SsrTraceOutputs actual;
      const SsrTraceStats stats = RunSsrTrace(in, {}, actual, KernelPath::kSimd);
      CHECK(test::SameBytes(actual.hitX, expected.hitX));
      CHECK(test::SameBytes(actual.hitY, expected.hitY));
      CHECK(test::SameBytes(actual.confidence, expected.confidence));
      CHECK(test::SameBytes(actual.iterations, expected.iterations));
      CHECK(stats.rays == expectedStats.rays);
      CHECK(stats.meanIterations == expectedStats.meanIterations);
      CHECK(stats.tilesTraced == expectedStats.tilesTraced);
    });
    CHECK(targets >= 2);
  });
}

}  // namespace
}  // namespace ssgi
