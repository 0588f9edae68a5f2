// The edge anti-aliasing: the G-buffer's edge coverage (passes/gbuffer_edges.cpp) and its blend
// (passes/antialias.h).
#include "passes/antialias.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "core/parallel.h"
#include "passes/gbuffer.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

// The share of the unit square centred at the origin with n . p + d >= 0, counted on a fine grid.
double CountedCoverage(double distance, double nx, double ny) {
  constexpr int kGrid = 512;
  size_t inside = 0;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i) {
      const double px = (i + 0.5) / kGrid - 0.5, py = (j + 0.5) / kGrid - 0.5;
      inside += nx * px + ny * py + distance >= 0.0;
    }
  return double(inside) / double(kGrid * kGrid);
}

TEST_CASE("edge coverage: BoxCoverage is the area of the unit square on the inside of the line", "[antialias]") {
  CHECK(BoxCoverage(0.0, 1.0, 0.0) == 0.5);
  CHECK(BoxCoverage(0.25, 1.0, 0.0) == 0.75);
  CHECK(BoxCoverage(-0.25, 0.0, -1.0) == 0.25);
  CHECK(BoxCoverage(0.8, 1.0, 0.0) == 1.0);
  CHECK(BoxCoverage(-0.8, 0.6, 0.8) == 0.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(0.0, 6.283185307179586), offset(-0.8, 0.8);
  for (int k = 0; k < 200; ++k) {
    const double a = angle(rng), d = offset(rng);
    const double nx = std::cos(a), ny = std::sin(a);
    CAPTURE(nx, ny, d);
    CHECK(BoxCoverage(d, nx, ny) == Approx(CountedCoverage(d, nx, ny)).margin(3.0 / 512.0));
    CHECK(BoxCoverage(d, nx, ny) + BoxCoverage(-d, nx, ny) == Approx(1.0).margin(1e-12));
  }
}

// One triangle in front of the background, seen by the default camera.
test::TestScene TriangleScene(int width, int height) {
  CameraDesc camera;
  test::TestScene scene = test::MakeScene(camera, width, height);
  scene.mesh.positions = {{-1.3f, -1.1f, 0.0f}, {1.6f, -0.4f, 0.2f}, {-0.2f, 1.4f, -0.3f}};
  scene.mesh.normals.assign(3, glm::vec3(0.0f, 0.0f, 1.0f));
  scene.mesh.uvs.assign(3, glm::vec2(0.0f));
  scene.mesh.indices = {0, 1, 2};
  scene.mesh.materials = {0};
  return scene;
}

TEST_CASE("edge anti-aliasing: a white triangle on black gets each edge pixel's covered area", "[antialias]") {
  constexpr int kWidth = 160, kHeight = 120;
  const test::TestScene scene = TriangleScene(kWidth, kHeight);
  const ViewProjection view = MakePerspective(scene.camera, kWidth, kHeight);
  GBufferOutputs g;
  const GBufferStats stats = RunGBuffer({scene, view}, {NormalEncoding::kOct24, true}, g);
  REQUIRE(g.edgeCoverage.xsize() == size_t(kWidth));
  CHECK(stats.edgePixels > 200);
  // White where the rasterizer drew the triangle.
  Plane3<float> image = MakePlane3<float>(kWidth, kHeight, 0.0f);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < 3; ++c)
        image.c[c].MutableRow(y)[x] = g.visibility.triangle.ConstRow(y)[x] == kNoTriangle ? 0.0f : 1.0f;
  Plane3<float> blended;
  RunAntialias({g.edgeCoverage, image}, blended);
  // The triangle on screen, and each pixel's covered share counted on a 32x32 grid.
  glm::dvec2 v[3];
  for (int i = 0; i < 3; ++i) {
    const glm::dvec4 clip = glm::dmat4(view.viewProjection) * glm::dvec4(glm::dvec3(scene.mesh.positions[i]), 1.0);
    v[i] = {(clip.x / clip.w * 0.5 + 0.5) * kWidth, (0.5 - clip.y / clip.w * 0.5) * kHeight};
  }
  const auto inside = [&](double px, double py) {
    double sign = 0.0;
    for (int i = 0; i < 3; ++i) {
      const glm::dvec2 a = v[i], b = v[(i + 1) % 3];
      const double e = (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x);
      if (sign == 0.0) sign = e >= 0.0 ? 1.0 : -1.0;
      if (e * sign < 0.0) return false;
    }
    return true;
  };
  double worstOff = 0.0, worstBlended = 0.0;
  size_t compared = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      // Near a corner a straight edge is not the boundary.
      bool nearCorner = false;
      for (const glm::dvec2& corner : v) nearCorner |= std::hypot(corner.x - x - 0.5, corner.y - y - 0.5) < 2.0;
      if (nearCorner) continue;
      constexpr int kGrid = 32;
      int covered = 0;
      for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) covered += inside(x + (i + 0.5) / kGrid, y + (j + 0.5) / kGrid);
      const double exact = double(covered) / (kGrid * kGrid);
      if (exact == 0.0 || exact == 1.0) continue;
      ++compared;
      worstOff = std::max(worstOff, std::abs(image.c[0].ConstRow(y)[x] - exact));
      worstBlended = std::max(worstBlended, std::abs(blended.c[0].ConstRow(y)[x] - exact));
    }
  CHECK(compared > 200);
  // Without anti-aliasing a pixel is off by up to its whole share; the blend is off by the word's
  // rounding, the grid's count and the rasterizer's snapped vertices.
  CHECK(worstOff > 0.4);
  CHECK(worstBlended < 0.03);
}

TEST_CASE("edge anti-aliasing: the SIMD row kernel equals the scalar definition on every target", "[antialias][simd]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> value(0.0f, 65504.0f);
  std::uniform_int_distribution<uint32_t> share(0, 64);
  for (size_t width = 1; width <= 67; ++width) {
    std::vector<float> rows[3][3];
    for (auto& channel : rows)
      for (auto& row : channel) {
        row.resize(width);
        for (float& f : row) f = rng() % 4 == 0 ? float(rng() % 3) : value(rng);
      }
    std::vector<uint32_t> coverage(width);
    for (uint32_t& word : coverage)
      word = rng() % 3 == 0 ? 0u : EdgeCoverageWord(share(rng), share(rng), share(rng), share(rng));
    const float* const in[3][3] = {{rows[0][0].data(), rows[0][1].data(), rows[0][2].data()},
                                   {rows[1][0].data(), rows[1][1].data(), rows[1][2].data()},
                                   {rows[2][0].data(), rows[2][1].data(), rows[2][2].data()}};
    std::vector<float> scalar(3 * width, -1.0f);
    float* const scalarOut[3] = {scalar.data(), scalar.data() + width, scalar.data() + 2 * width};
    AntialiasRowScalar(coverage.data(), in, width, scalarOut);
    CAPTURE(width);
    test::ForEachSimdTarget([&](const char* target) {
      std::vector<float> simd(3 * width, -1.0f);
      float* const simdOut[3] = {simd.data(), simd.data() + width, simd.data() + 2 * width};
      AntialiasRowSimd(coverage.data(), in, width, simdOut);
      CAPTURE(target);
      CHECK(test::FirstDifferentBits(simd.data(), scalar.data(), 3 * width) == 3 * width);
    });
  }
}

TEST_CASE("edge anti-aliasing: the same bytes on the default scene at any thread count, on any kernel path, in place",
          "[antialias][simd]") {
  const test::DefaultScene defaults = test::LoadDefaultScene();
  for (const auto& [width, height] : {std::pair{331, 197}, std::pair{67, 45}, std::pair{1, 1}}) {
    CAPTURE(width, height);
    FrameConfig config = defaults.config;
    config.width = width;
    config.height = height;
    config.antialiasing = Antialiasing::kEdge;
    config.shadowMap.resolution = 512;
    const Frame frame = RenderFrame(defaults.scene, config);
    REQUIRE(frame.gbuffer.edgeCoverage.xsize() == size_t(width));
    if (width > 1) CHECK(frame.antialias);
    Plane3<float> reference;
    RunAntialias({frame.gbuffer.edgeCoverage, frame.Composed()}, reference, KernelPath::kScalar);
    const auto same = [](const Plane3<float>& a, const Plane3<float>& b) { return test::SameBytes(a, b); };
    if (frame.antialias) CHECK(same(frame.Result(), reference));
    for (int threads : {1, 2, 3}) {
      const ThreadLimit limit(threads);
      GBufferOutputs g;
      RunGBuffer({defaults.scene, frame.view}, {config.normalEncoding, true}, g);
      CHECK(test::SameBytes(g.edgeCoverage, frame.gbuffer.edgeCoverage));
      Plane3<float> inPlace = test::CopyOf(frame.Composed());
      RunAntialias({frame.gbuffer.edgeCoverage, inPlace}, inPlace);
      CHECK(same(inPlace, reference));
    }
    CHECK(test::TargetsWhereKernelPathsDiffer(
              [&](KernelPath kernels) {
                Plane3<float> out;
                RunAntialias({frame.gbuffer.edgeCoverage, frame.Composed()}, out, kernels);
                return out;
              },
              same) == "");
  }
}

TEST_CASE("edge anti-aliasing: planned (no edges, no pass), and off changes no byte", "[antialias][frame]") {
  const test::DefaultScene defaults = test::LoadDefaultScene();
  FrameConfig config = defaults.config;
  config.width = 96;
  config.height = 64;
  config.shadowMap.resolution = 256;
  config.antialiasing = Antialiasing::kOff;
  const Frame off = RenderFrame(defaults.scene, config);
  CHECK_FALSE(off.antialias);
  CHECK(off.plan.antialias.why == "switched off");
  CHECK(off.gbuffer.edgeCoverage.xsize() == 0);
  CHECK_FALSE(off.stats.antialias);
  config.antialiasing = Antialiasing::kEdge;
  const Frame edge = RenderFrame(defaults.scene, config);
  CHECK(edge.antialias);
  CHECK(edge.stats.gbuffer->edgePixels == edge.stats.antialias->edgePixels);
  const FramePlan counted =
      PlanFrame(defaults.scene, config, edge.gbuffer.gbuffer, edge.gbuffer.edgeCoverage, edge.view, true);
  CHECK(counted.antialias.pixels == edge.stats.antialias->edgePixels);
  CHECK(counted.antialias.tiles > 0);
  CHECK(test::SameBytes(off.Result().c[0], edge.Composed().c[0]));
  CHECK_FALSE(test::SameBytes(off.Result().c[0], edge.Result().c[0]));
  // A camera that sees only the background: no edge, no pass.
  const Frame none = RenderFrame(test::FacingTheSky(defaults.scene), config);
  CHECK_FALSE(none.antialias);
  CHECK(none.plan.antialias.why == "no pixel lies on a geometric edge");
  CHECK_FALSE(none.stats.antialias);
}

}  // namespace
}  // namespace ssgi
