// The llvmpipe peer (bench/llvmpipe_bench.cpp) does ssgi's work: drawn through OpenGL on llvmpipe,
// the benchmarks' scenes cover the same pixels as ssgi's rasterizer, and those pixels hold the same
// surface, except at pixels whose centre lies within rounding distance of a triangle edge. There
// the two may differ as two conforming rasterizers may (docs/pipeline.md §Rasterizer; the Khronos
// CTS judges rasterization the same way). Skips with a warning where no llvmpipe context can be had.
#include <catch2/catch.hpp>

#ifndef SSGI_LLVMPIPE_PEER
TEST_CASE("llvmpipe peer: same coverage as ssgi", "[bench][llvmpipe]") {
  WARN("skipped: the llvmpipe peer is not built (no EGL/OpenGL development files, or SSGI_BUILD_BENCH off)");
}
#else

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bench/bench_scene.h"
#include "bench/egl_context.h"
#include "bench/gl_gbuffer.h"
#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/raster/raster.h"
#include "passes/gbuffer.h"

namespace ssgi::test {
namespace {

// Both rasterizers snap vertices to 1/256 pixel, each moving an edge by up to sqrt(2)/512 pixel;
// twice that leaves room for their different float transforms.
constexpr double kRoundingDistancePixels = 1.0 / 128.0;
// Away from edges: relative view depth (measured 0.00089 at most, on small triangles seen edge-on,
// whose depth plane the snapping tilts most) and normal direction (measured 0.25 deg).
constexpr double kDepthTolerance = 2e-3;
constexpr double kNormalToleranceDegrees = 0.5;

// The screen positions (pixels, y down, docs/pipeline.md §Conventions) of every vertex, and whether a
// pixel centre lies within rounding distance of an edge of any triangle. Only for vertices in front
// of the camera, as in the scenes here.
class TriangleEdges {
 public:
  TriangleEdges(const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices,
                const ViewProjection& view)
      : indices_(indices) {
    for (const glm::vec3& p : positions) {
      const glm::dvec4 clip = glm::dmat4(view.viewProjection) * glm::dvec4(p, 1.0);
      screen_.emplace_back((clip.x / clip.w * 0.5 + 0.5) * view.width, (0.5 - clip.y / clip.w * 0.5) * view.height);
    }
  }
  bool NearAnEdge(int px, int py) const {
    const glm::dvec2 centre(px + 0.5, py + 0.5);
    for (size_t t = 0; t < indices_.size(); t += 3) {
      for (int e = 0; e < 3; ++e) {
        const glm::dvec2 a = screen_[indices_[t + e]], b = screen_[indices_[t + (e + 1) % 3]];
        const glm::dvec2 ab = b - a;
        const double along = std::clamp(glm::dot(centre - a, ab) / std::max(glm::dot(ab, ab), 1e-300), 0.0, 1.0);
        if (glm::length(centre - (a + along * ab)) <= kRoundingDistancePixels) return true;
      }
    }
    return false;
  }

 private:
  const std::vector<uint32_t>& indices_;
  std::vector<glm::dvec2> screen_;
};

double AngleDegrees(glm::vec3 a, glm::vec3 b) {
  return glm::degrees(std::acos(std::clamp(double(glm::dot(a, b)), -1.0, 1.0)));
}

std::unique_ptr<LlvmpipeContext> OpenOrWarn() {
  std::string error;
  std::unique_ptr<LlvmpipeContext> context = LlvmpipeContext::Open(2, error);
  if (context == nullptr) WARN("skipped: no llvmpipe context: " << error);
  return context;
}

TEST_CASE("llvmpipe peer: the G-buffer of the 10k knot matches ssgi's but at edges", "[bench][llvmpipe]") {
  const std::unique_ptr<LlvmpipeContext> context = OpenOrWarn();
  if (context == nullptr) return;
  const BenchScene& bench = KnotScene(10000);
  REQUIRE(bench.error.empty());
  const Scene& scene = bench.scene;
  constexpr int kSize = 1024;  // the benchmark's
  const ViewProjection view = MakePerspective(scene.camera, kSize, kSize);

  GBufferOutputs ours;
  RunGBuffer({scene, view}, GBufferParams{}, ours);
  const GlMesh mesh(scene.mesh.positions, scene.mesh.normals, scene.mesh.indices);
  const GlGBufferPass pass(kSize, kSize);
  pass.Draw(mesh, view, scene.materials[0]);
  const GBuffer peer = pass.Read();

  const TriangleEdges edges(scene.mesh.positions, scene.mesh.indices, view);
  size_t covered = 0, coverageDiffers = 0, surfaceDiffers = 0;
  double maxDepthError = 0.0, maxNormalDegrees = 0.0;  // over the pixels not at an edge
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const auto word = [x, y](const GBuffer& g, int w) { return g.word[w].ConstRow(size_t(y))[x]; };
      const float ourDepth = UnpackDepth(word(ours.gbuffer, 2)), peerDepth = UnpackDepth(word(peer, 2));
      const bool ourCover = ourDepth != kBackgroundDepth, peerCover = peerDepth != kBackgroundDepth;
      covered += ourCover;
      if (ourCover != peerCover) {
        ++coverageDiffers;
        INFO("pixel (" << x << ", " << y << ") covered by " << (ourCover ? "ssgi" : "llvmpipe") << " only");
        REQUIRE(edges.NearAnEdge(x, y));
        continue;
      }
      if (!ourCover) {
        REQUIRE(word(peer, 0) == 0u);
        REQUIRE(word(peer, 1) == 0u);
        continue;
      }
      // Covered by both: the same material and the same surface, word 3 left lit. The depth within
      // kDepthTolerance: ssgi inverts a depth key interpolated over the snapped vertices, llvmpipe
      // interpolates the view depth; the normal within kNormalToleranceDegrees, a few oct24 steps.
      const double depthError = std::abs(double(peerDepth) - ourDepth) / ourDepth;
      const double normalDegrees = AngleDegrees(UnpackNormal(word(ours.gbuffer, 1), NormalEncoding::kOct24),
                                                UnpackNormal(word(peer, 1), NormalEncoding::kOct24));
      const bool sameSurface = depthError <= kDepthTolerance && normalDegrees <= kNormalToleranceDegrees &&
                               word(ours.gbuffer, 0) == word(peer, 0) &&
                               (word(ours.gbuffer, 1) >> 24) == (word(peer, 1) >> 24);
      if (!sameSurface) {
        ++surfaceDiffers;
        INFO("pixel (" << x << ", " << y << "): depth " << ourDepth << " / " << peerDepth << ", normals "
                       << normalDegrees << " deg apart, words 0 " << word(ours.gbuffer, 0) << " / "
                       << word(peer, 0));
        REQUIRE(edges.NearAnEdge(x, y));
        continue;
      }
      maxDepthError = std::max(maxDepthError, depthError);
      maxNormalDegrees = std::max(maxNormalDegrees, normalDegrees);
      REQUIRE(word(peer, 3) == kShadowLit);
    }
  }
  CHECK(double(covered) / (kSize * kSize) > 0.6);  // the knot fills most of the image
  WARN("llvmpipe vs ssgi, 10k knot at 1024x1024 (" << context->renderer() << "): " << covered
                                                   << " pixels covered; at edges only, coverage differs at "
                                                   << coverageDiffers << ", the surface at " << surfaceDiffers
                                                   << "; elsewhere depth within " << maxDepthError
                                                   << " (relative), normals within " << maxNormalDegrees << " deg");
}

TEST_CASE("llvmpipe peer: the fill-rate triangles' visibility matches ssgi's but at edges", "[bench][llvmpipe]") {
  const std::unique_ptr<LlvmpipeContext> context = OpenOrWarn();
  if (context == nullptr) return;
  const FillrateScene& scene = FillrateTriangles(500);  // the fewest triangles, still 8 layers deep
  RasterInput input;
  input.positions = scene.positions.data();
  input.vertexCount = scene.positions.size();
  input.indices = scene.indices.data();
  input.triangleCount = scene.TriangleCount();
  VisibilityBuffer ours = MakeVisibilityBuffer(kFillrateSize, kFillrateSize, RasterOutput::kVisibility);
  Rasterize(input, scene.view, RasterOutput::kVisibility, ours);
  const GlMesh mesh(scene.positions, {}, scene.indices);
  const GlVisibilityPass pass(kFillrateSize, kFillrateSize);
  pass.Draw(mesh, scene.view);
  const Plane<uint32_t> peer = pass.ReadTarget(0);

  const TriangleEdges edges(scene.positions, scene.indices, scene.view);
  size_t differs = 0;
  for (int y = 0; y < kFillrateSize; ++y) {
    for (int x = 0; x < kFillrateSize; ++x) {
      const uint32_t ourTriangle = ours.triangle.ConstRow(size_t(y))[x], peerTriangle = peer.ConstRow(size_t(y))[x];
      if (ourTriangle == peerTriangle) continue;
      ++differs;
      INFO("pixel (" << x << ", " << y << "): triangle " << ourTriangle << " / " << peerTriangle);
      REQUIRE(edges.NearAnEdge(x, y));
    }
  }
  WARN("llvmpipe vs ssgi, fill-rate triangles of 500 pixels: the front triangle differs at " << differs
                                                                                          << " pixels, all at edges");
}

}  // namespace
}  // namespace ssgi::test

#endif
