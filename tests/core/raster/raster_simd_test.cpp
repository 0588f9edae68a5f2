// The rasterizer's Highway tile kernel (core/raster/raster_simd.cpp) against its scalar definition
// (core/raster/raster.cpp), bit for bit, on every compiled and supported target: depth keys, triangle
// indices and coverage counts of the default scene from its camera and from its sun (depth only, both
// faces), with cut-outs, and of triangles whose edges are too long for the kernel's 32-bit lanes; and
// the batched triangle set-up against the scalar one.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "core/raster/raster.h"
#include "core/raster/raster_tile.h"
#include "core/raster/scene_raster_input.h"
#include "core/texture.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

struct RasterResult {
  VisibilityBuffer visibility;
  Plane<uint32_t> coverage;
};

bool SameResult(const RasterResult& a, const RasterResult& b) {
  const bool sameTriangles =
      a.visibility.triangle.xsize() == 0 || test::SameBytes(a.visibility.triangle, b.visibility.triangle);
  const bool sameCoverage = a.coverage.xsize() == 0 || test::SameBytes(a.coverage, b.coverage);
  return test::SameBytes(a.visibility.depthKey, b.visibility.depthKey) && sameTriangles && sameCoverage;
}

// Rasterizes `input` seen through `view` with either kernel path, counting coverage or not (as
// frames do not).
auto RunOf(const RasterInput& input, const ViewProjection& view, RasterOutput output, bool countCoverage = true) {
  return [&input, &view, output, countCoverage](KernelPath kernels) {
    RasterResult result{MakeVisibilityBuffer(view.width, view.height, output),
                        countCoverage ? MakePlane<uint32_t>(view.width, view.height, 0u) : Plane<uint32_t>()};
    Rasterize(input, view, output, result.visibility, countCoverage ? &result.coverage : nullptr, kernels);
    return result;
  };
}

size_t CountDrawn(const VisibilityBuffer& visibility) {
  size_t drawn = 0;
  for (size_t y = 0; y < visibility.depthKey.ysize(); ++y)
    for (size_t x = 0; x < visibility.depthKey.xsize(); ++x) drawn += visibility.depthKey.ConstRow(y)[x] != 0.0f;
  return drawn;
}

// The default scene's sun as an orthographic view over the whole board, as a shadow map sees it.
ViewProjection SunView(const Scene& scene, int width, int height) {
  const glm::vec3 direction = glm::normalize(scene.directionalLights.front().direction);
  return MakeOrthographic(-6.0f * direction, direction, {1.0f, 0.0f, 0.0f}, 3.2f, 3.2f, 0.1f, 12.0f, width, height);
}

// An orthographic view down -z from the origin, depths 0.1 to farPlane, whose image is `size` pixels of
// one world unit each, centred on the z axis.
ViewProjection PixelView(glm::ivec2 size, float farPlane) {
  return MakeOrthographic({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, {0.0f, 1.0f, 0.0f}, 0.5f * float(size.x),
                          0.5f * float(size.y), 0.1f, farPlane, size.x, size.y);
}

// Every output of the raster of `input` (visibility or depth only, coverage counted or not): at least
// `minDrawn` pixels drawn, and the same bytes on every target.
void CheckEveryOutputAgrees(const RasterInput& input, const ViewProjection& view, size_t minDrawn) {
  for (const RasterOutput output : {RasterOutput::kVisibility, RasterOutput::kDepthOnly}) {
    for (const bool countCoverage : {false, true}) {
      const auto run = RunOf(input, view, output, countCoverage);
      CHECK(CountDrawn(run(KernelPath::kScalar).visibility) >= minDrawn);
      CHECK(test::TargetsWhereKernelPathsDiffer(run, SameResult) == "");
    }
  }
}

const std::vector<glm::ivec2> kSizes = {glm::ivec2(1024, 1024), glm::ivec2(1, 1), glm::ivec2(67, 45),
                                        glm::ivec2(1023, 769)};

TEST_CASE("raster: the SIMD tile kernel gives the scalar bytes on every target, default scene", "[raster][simd]") {
  const test::DefaultScene loaded = test::LoadDefaultScene();
  const Scene& scene = loaded.scene;
  for (const glm::ivec2 size : kSizes) {
    const ViewProjection camera = MakePerspective(scene.camera, size.x, size.y);
    const ViewProjection sun = SunView(scene, size.x, size.y);
    const SceneRasterInput cameraInput(scene, camera, true);
    const SceneRasterInput sunInput(scene, sun, false);
    CAPTURE(size.x, size.y);
    const auto visibility = RunOf(cameraInput.Get(), camera, RasterOutput::kVisibility);
    CHECK(CountDrawn(visibility(KernelPath::kScalar).visibility) > size_t(size.x * size.y) / 3);
    CHECK(test::TargetsWhereKernelPathsDiffer(visibility, SameResult) == "");
    const auto depthOnly = RunOf(sunInput.Get(), sun, RasterOutput::kDepthOnly);
    CHECK(CountDrawn(depthOnly(KernelPath::kScalar).visibility) > size_t(size.x * size.y) / 3);
    CHECK(test::TargetsWhereKernelPathsDiffer(depthOnly, SameResult) == "");
    for (const RasterOutput output : {RasterOutput::kVisibility, RasterOutput::kDepthOnly}) {
      const auto uncounted = RunOf(output == RasterOutput::kVisibility ? cameraInput.Get() : sunInput.Get(),
                                   output == RasterOutput::kVisibility ? camera : sun, output, false);
      CHECK(test::TargetsWhereKernelPathsDiffer(uncounted, SameResult) == "");
    }
  }
}

TEST_CASE("raster: the SIMD tile kernel gives the scalar bytes on every target, cut-outs", "[raster][simd]") {
  Scene scene = test::LoadDefaultScene().scene;
  // Every surface cut out by a checker of 8x8 texels, 4 per metre in x and z (and y, for the walls).
  std::vector<uint8_t> rgba(8 * 8 * 4, 255);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) rgba[(size_t(y) * 8 + size_t(x)) * 4 + 3] = (x + y) % 2 ? 255 : 0;
  scene.textures.push_back(MakeTexture(8, 8, std::move(rgba), TextureEncoding::kLinear));
  for (Material& material : scene.materials) material.alphaTexture = int32_t(scene.textures.size() - 1);
  for (size_t i = 0; i < scene.mesh.positions.size(); ++i) {
    const glm::vec3 p = scene.mesh.positions[i];
    scene.mesh.uvs[i] = {0.5f * p.x, 0.5f * (p.z + p.y)};
  }
  for (const glm::ivec2 size : kSizes) {
    const ViewProjection camera = MakePerspective(scene.camera, size.x, size.y);
    const SceneRasterInput input(scene, camera, true);
    const auto run = RunOf(input.Get(), camera, RasterOutput::kVisibility);
    CAPTURE(size.x, size.y);
    // The cut-outs take away about half of what the scene covers.
    if (size.x > 1) CHECK(CountDrawn(run(KernelPath::kScalar).visibility) < size_t(size.x * size.y) * 4 / 10);
    CHECK(test::TargetsWhereKernelPathsDiffer(run, SameResult) == "");
  }
}

TEST_CASE("raster: the SIMD tile kernel gives the scalar bytes on every target, edges too long for 32 bits",
          "[raster][simd]") {
  // A ground 2 km wide in two triangles, seen from 1.5 m above it: clipped to the guard band, its
  // edges span tens of thousands of pixels (ScreenTriangle::edgesFit32Bits is false); and a small
  // quad in front, which fits.
  Scene scene;
  test::AddGround(scene.mesh, 1000.0f);
  test::AddQuad(scene.mesh, {-0.5f, 0.2f, -2.0f}, {1.0f, 0.1f, 0.0f}, {0.1f, 0.8f, 0.3f});
  scene.materials.push_back(Material{});
  scene.camera.position = {0.3f, 1.5f, 2.0f};
  scene.camera.target = {0.0f, 0.0f, -3.0f};
  for (const glm::ivec2 size : kSizes) {
    const ViewProjection camera = MakePerspective(scene.camera, size.x, size.y);
    const SceneRasterInput input(scene, camera, true);
    const auto run = RunOf(input.Get(), camera, RasterOutput::kVisibility);
    CAPTURE(size.x, size.y);
    CHECK(CountDrawn(run(KernelPath::kScalar).visibility) > size_t(size.x * size.y) / 2);
    CHECK(test::TargetsWhereKernelPathsDiffer(run, SameResult) == "");
  }
}

TEST_CASE("raster: the SIMD tile kernel gives the scalar bytes on every target, edges through sample positions",
          "[raster][simd]") {
  // Orthographic views in which world (x, y) is image position (x + W / 2, H / 2 - y): vertices at
  // pixel centres, edges along rows and diagonals through pixel centres, where E = 0 and the
  // top-left rule decides. Both long edges (64-bit path) and short ones (32-bit lanes).
  const std::vector<glm::vec2> triangles = {
      {-5000, 300}, {6000, 300},  {500, -5200},  // long: a row, two diagonals
      {6000, 300},  {-5000, 300}, {500, 5800},   // sharing the row edge
      {10, 10},     {10, 40},     {40, 10},      // short, sharing a diagonal
      {40, 10},     {10, 40},     {40, 40},      //
      {100, 50},    {100, 650},   {700, 650},    // across tiles
  };
  for (const glm::ivec2 size : kSizes) {
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
    for (const glm::vec2 pixel : triangles) {
      indices.push_back(uint32_t(positions.size()));
      positions.push_back({pixel.x + 0.5f - 0.5f * float(size.x), 0.5f * float(size.y) - pixel.y - 0.5f, 0.0f});
    }
    const ViewProjection view = MakeOrthographic({0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, -1.0f}, {0.0f, 1.0f, 0.0f},
                                                 0.5f * float(size.x), 0.5f * float(size.y), 0.1f, 2.0f, size.x,
                                                 size.y);
    const RasterInput input{positions.data(), positions.size(), indices.data(), indices.size() / 3, nullptr, {}};
    const auto run = RunOf(input, view, RasterOutput::kVisibility);
    CAPTURE(size.x, size.y);
    CHECK(CountDrawn(run(KernelPath::kScalar).visibility) == size_t(size.x * size.y));
    CHECK(test::TargetsWhereKernelPathsDiffer(run, SameResult) == "");
  }
}


// Quads over the whole image at several depths, two of them in the same plane (ties keep the earlier
// one) and one tilted through the others in x and y: most tiles are covered whole by several
// triangles, whose every block the kernel accepts, with and without coverage counting.
TEST_CASE("raster: the SIMD tile kernel gives the scalar bytes on every target, tiles covered whole",
          "[raster][simd]") {
  for (const glm::ivec2 size : kSizes) {
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
    // Depths at the bottom-left, bottom-right, top-right and top-left corners.
    const auto quad = [&](float z00, float z10, float z11, float z01) {
      const uint32_t first = uint32_t(positions.size());
      const float hx = 0.6f * float(size.x), hy = 0.6f * float(size.y);
      positions.insert(positions.end(), {{-hx, -hy, z00}, {hx, -hy, z10}, {hx, hy, z11}, {-hx, hy, z01}});
      indices.insert(indices.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
    };
    quad(-1.2f, -1.2f, -1.2f, -1.2f);
    quad(-0.6f, -0.6f, -0.6f, -0.6f);
    quad(-1.6f, -0.25f, -0.15f, -1.5f);  // tilted in x and y
    quad(-0.6f, -0.6f, -0.6f, -0.6f);
    quad(-0.9f, -0.9f, -0.9f, -0.9f);
    const ViewProjection view = PixelView(size, 2.0f);
    const RasterInput input{positions.data(), positions.size(), indices.data(), indices.size() / 3, nullptr, {}};
    CAPTURE(size.x, size.y);
    CheckEveryOutputAgrees(input, view, size_t(size.x * size.y));
    // The tilted quad wins on its near side and the first of the two coplanar ones elsewhere.
    const auto visible = RunOf(input, view, RasterOutput::kVisibility)(KernelPath::kScalar).visibility.triangle;
    const uint32_t left = visible.ConstRow(size_t(size.y / 2))[0], right = visible.ConstRow(size_t(size.y / 2))[size.x - 1];
    if (size.x > 1) {
      CHECK(left / 2 == 1);
      CHECK(right / 2 == 2);
    }
  }
}

// Depth-only rasters pass over the blocks a triangle cannot reach in front of what they hold (the
// twin's hidden-block test, core/raster/raster_simd.cpp): layers of quads over the whole image, tilted a
// little each way and a millionth of the depth range apart, in a random order, so that many blocks
// are hidden and many others are reached by a hair, within the test's margin.
TEST_CASE("raster: the SIMD tile kernel gives the scalar bytes on every target, near-coplanar layers",
          "[raster][simd]") {
  std::mt19937 rng(14);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  for (const glm::ivec2 size : {glm::ivec2(256, 192), glm::ivec2(67, 45)}) {
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
    std::vector<int> order(48);
    for (size_t i = 0; i < order.size(); ++i) order[i] = int(i);
    std::shuffle(order.begin(), order.end(), rng);
    for (const int layer : order) {
      const float depth = -1.0f + 1e-6f * float(layer), tiltX = 2e-6f * unit(rng), tiltY = 2e-6f * unit(rng);
      const uint32_t first = uint32_t(positions.size());
      const float hx = 0.6f * float(size.x), hy = 0.6f * float(size.y);
      for (const glm::vec2 corner : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)})
        positions.push_back({corner.x * hx, corner.y * hy, depth + tiltX * corner.x + tiltY * corner.y});
      indices.insert(indices.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
    }
    const ViewProjection view = PixelView(size, 2.0f);
    const RasterInput input{positions.data(), positions.size(), indices.data(), indices.size() / 3, nullptr, {}};
    CAPTURE(size.x, size.y);
    const auto run = RunOf(input, view, RasterOutput::kDepthOnly, false);
    CHECK(CountDrawn(run(KernelPath::kScalar).visibility) == size_t(size.x * size.y));
    CHECK(test::TargetsWhereKernelPathsDiffer(run, SameResult) == "");
  }
}

// `count` triangles of the pixel view of `size` (PixelView), triangle i with its vertices within
// extent(i) pixels of a random anchor on or near the image, at random depths and facings; every
// fifth with vertices on pixel centres (edges through samples), every fiftieth drawn twice (ties).
template <class Extent>
void AddRandomTriangles(glm::ivec2 size, size_t count, const Extent& extent, std::mt19937& rng,
                        std::vector<glm::vec3>& positions, std::vector<uint32_t>& indices) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (size_t i = 0; i < count; ++i) {
    const glm::vec2 anchor(unit(rng) * float(size.x + 4) - 2.0f, unit(rng) * float(size.y + 4) - 2.0f);
    const float depth = -1.0f - unit(rng);
    const uint32_t first = uint32_t(positions.size());
    for (int v = 0; v < 3; ++v) {
      glm::vec2 pixel = anchor + extent(i) * glm::vec2(unit(rng), unit(rng));
      if (i % 5 == 0) pixel = glm::floor(pixel) + 0.5f;  // on a pixel centre
      positions.push_back({pixel.x - 0.5f * float(size.x), 0.5f * float(size.y) - pixel.y, depth + 0.1f * unit(rng)});
    }
    indices.insert(indices.end(), {first, first + 1, first + 2});
    if (i % 50 == 0) indices.insert(indices.end(), {first, first + 1, first + 2});  // a tie
  }
}

// A dense mesh of small triangles, as far-away detail or a scanned model gives: more than one per
// kSmallTrianglePixels pixels in every tile, so the twin takes its box path (core/raster/raster_simd.cpp)
// in depth-only rasters too, from below a pixel to a few pixels wide, some across tile edges and the
// image's; and large triangles that reach into a tile by a few pixels only.
TEST_CASE("raster: the SIMD tile kernel gives the scalar bytes on every target, small triangles",
          "[raster][simd]") {
  std::mt19937 rng(15);
  for (const glm::ivec2 size : {glm::ivec2(256, 192), glm::ivec2(67, 45)}) {
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
    AddRandomTriangles(
        size, size_t(size.x) * size_t(size.y) / 2,
        [](size_t i) { return i % 4 == 0 ? 0.5f : (i % 4 == 1 ? 2.0f : (i % 4 == 2 ? 4.0f : 6.0f)); }, rng,
        positions, indices);
    // Large ones in front, whose part in a tile is a 3x3 corner (cut by the tile's edges or the
    // image's): their edge values there are far beyond 32 bits.
    const auto addFront = [&](glm::vec2 a, glm::vec2 b, glm::vec2 c) {
      const uint32_t first = uint32_t(positions.size());
      for (const glm::vec2 pixel : {a, b, c})
        positions.push_back({pixel.x - 0.5f * float(size.x), 0.5f * float(size.y) - pixel.y, -0.5f});
      indices.insert(indices.end(), {first, first + 1, first + 2});
    };
    for (const glm::vec2 corner : {glm::vec2(64, 64), glm::vec2(128, 128), glm::vec2(0, 0)})
      addFront(corner + 2.6f, corner + glm::vec2(-700.0f, 2.7f), corner + glm::vec2(2.7f, -700.0f));
    const glm::vec2 end(size);
    addFront(end - 2.6f, end + glm::vec2(700.0f, -2.7f), end + glm::vec2(-2.7f, 700.0f));
    const ViewProjection view = PixelView(size, 3.0f);
    const RasterInput input{positions.data(), positions.size(), indices.data(), indices.size() / 3, nullptr, {}};
    CAPTURE(size.x, size.y);
    CheckEveryOutputAgrees(input, view, size_t(size.x * size.y) / 2);
  }
}

// Triangles of up to 40 pixels each way, fewer than one per kSmallTrianglePixels pixels, so the twin
// takes its box path for those whose samples fit a 32x32 box (core/raster/raster_simd.cpp): parts in one
// block and across two, from even and odd rows, cut by tile edges and the image's, and triangles a
// little too large for the box.
TEST_CASE("raster: the SIMD tile kernel gives the scalar bytes on every target, triangles of a few blocks",
          "[raster][simd]") {
  std::mt19937 rng(16);
  for (const glm::ivec2 size : {glm::ivec2(256, 192), glm::ivec2(67, 45), glm::ivec2(130, 67)}) {
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
    AddRandomTriangles(
        size, size_t(size.x) * size_t(size.y) / 24, [](size_t i) { return 2.0f + float(i % 39); }, rng, positions,
        indices);
    const ViewProjection view = PixelView(size, 3.0f);
    const RasterInput input{positions.data(), positions.size(), indices.data(), indices.size() / 3, nullptr, {}};
    CAPTURE(size.x, size.y);
    CheckEveryOutputAgrees(input, view, size_t(size.x * size.y) / 8);
  }
}

// Vertices all around two perspective cameras and an orthographic one: in the view, behind the
// camera, exactly on the near and far planes (distance 0, inside) and near them, beyond the guard band,
// far away; counts that leave a partial vector.
TEST_CASE("raster: the vertex projection twin equals the scalar projection on every target", "[raster][simd]") {
  std::mt19937 rng(16);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  CameraDesc tilted;
  tilted.position = {0.3f, 1.2f, 4.0f};
  tilted.target = {0.0f, 0.2f, 0.0f};
  CameraDesc axial;  // at the origin, looking down -z: w is -z exactly
  axial.position = {0.0f, 0.0f, 0.0f};
  axial.target = {0.0f, 0.0f, -1.0f};
  for (const glm::ivec2 size : kSizes) {
    size_t onPlane = 0;
    for (const ViewProjection& view :
         {MakePerspective(tilted, size.x, size.y), MakePerspective(axial, size.x, size.y),
          MakeOrthographic({0.0f, 0.0f, 3.0f}, {0.0f, 0.0f, -1.0f}, {0.0f, 1.0f, 0.0f}, 2.0f, 1.5f, 0.1f, 6.0f, size.x,
                           size.y)}) {
      std::vector<glm::vec3> positions;
      for (int i = 0; i < 3001; ++i) {
        const float scale = i % 7 == 0 ? 1e5f : (i % 7 == 1 ? 30.0f : 3.0f);
        positions.push_back(scale * glm::vec3(unit(rng), unit(rng), unit(rng)));
      }
      // The points a few float steps of one coordinate around the near and far planes (the
      // perspective views' far plane is at infinity) that lie on them.
      const glm::mat4 toWorld = glm::inverse(view.viewProjection);
      const ClipPlanes planes(size.x, size.y);
      for (const float ndcZ : {1.0f, 0.0f}) {
        const glm::vec4 onPlaneNdc = toWorld * glm::vec4(0.1f, 0.2f, ndcZ, 1.0f);
        if (!(std::abs(onPlaneNdc.w) > 1e-20f)) continue;
        for (int c = 0; c < 3; ++c) {
          glm::vec3 point = glm::vec3(onPlaneNdc) / onPlaneNdc.w;
          for (int step = 0; step < 64; ++step) point[c] = std::nextafter(point[c], -1e30f);
          for (int step = 0; step < 128; ++step, point[c] = std::nextafter(point[c], 1e30f)) {
            const std::array<double, ClipPlanes::kCount> distance =
                planes.Distances(glm::dvec4(ClipPosition(point, view.viewProjection)));
            if (distance[0] == 0.0 || distance[1] == 0.0) {
              positions.push_back(point);
              ++onPlane;
            }
          }
        }
      }
      CAPTURE(size.x, size.y, view.orthographic);
      for (const size_t count : {positions.size(), size_t(1), size_t(5)}) {
        std::vector<ProjectedVertex> expected(count);
        ProjectVerticesScalar(positions.data(), count, view.viewProjection, size.x, size.y, expected.data());
        size_t inside = 0;
        for (const ProjectedVertex& v : expected) inside += v.Outside() == 0;
        if (count == positions.size()) CHECK((inside > count / 5 && inside < count * 9 / 10));
        const size_t targets = test::ForEachSimdTarget([&](const char* target) {
          std::vector<ProjectedVertex> actual(count);
          ProjectVerticesSimd(positions.data(), count, view.viewProjection, size.x, size.y, actual.data());
          CAPTURE(target, count);
          CHECK(std::memcmp(actual.data(), expected.data(), count * sizeof(ProjectedVertex)) == 0);
        });
        CHECK(targets >= 2);
      }
    }
    CHECK(onPlane > 0);
  }
}

// Random projected vertices: most inside a width x height image, some out to the guard band's edge
// (2^23.6 in sub-pixel units), some outside a clip plane; triangles that share vertices (zero area),
// lie on a line, face either way, with random flags.
TEST_CASE("raster: the batched triangle set-up equals the scalar set-up on every target", "[raster][simd]") {
  std::mt19937 rng(12);
  for (const glm::ivec2 size : kSizes) {
    CAPTURE(size.x, size.y);
    constexpr size_t kVertices = 600, kTriangles = 4000;
    std::vector<ProjectedVertex> vertices(kVertices);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const int32_t guard = 3 * 16384 * int32_t(kSubPixelScale) - 1;
    for (size_t i = 0; i < kVertices; ++i) {
      ProjectedVertex& v = vertices[i];
      const double kind = unit(rng);
      const auto coordinate = [&](int extent) {
        if (kind < 0.15) return int32_t((2.0 * unit(rng) - 1.0) * double(guard));
        return int32_t(unit(rng) * double(extent + 2) * kSubPixelScale) - int32_t(kSubPixelScale);
      };
      v.snapped = {coordinate(size.x), coordinate(size.y), unit(rng)};
      if (i % 3 != 0 && kind < 0.6) {  // within four pixels of the previous vertex: small triangles
        const SnappedVertex& previous = vertices[i - 1].snapped;
        if (previous.y != ProjectedVertex::kOutsideClipPlanes)
          v.snapped = {previous.x + int32_t((2.0 * unit(rng) - 1.0) * 4.0 * kSubPixelScale),
                       previous.y + int32_t((2.0 * unit(rng) - 1.0) * 4.0 * kSubPixelScale), unit(rng)};
      }
      if (i % 50 == 7) v.snapped = vertices[i - 1].snapped;  // a repeated position: zero area
      if (kind > 0.9) v.snapped = {int32_t(1) << (rng() % 6), ProjectedVertex::kOutsideClipPlanes, 0.0};
    }
    std::vector<uint32_t> indices(3 * kTriangles);
    std::vector<uint8_t> flags(kTriangles);
    for (size_t t = 0; t < kTriangles; ++t) {
      for (int k = 0; k < 3; ++k) indices[3 * t + size_t(k)] = uint32_t(rng() % kVertices);
      if (t % 3 == 0) {  // three consecutive vertices: often close together
        const uint32_t firstVertex = uint32_t(rng() % (kVertices / 3)) * 3;
        for (int k = 0; k < 3; ++k) indices[3 * t + size_t(k)] = firstVertex + uint32_t(k);
      }
      if (t % 97 == 3) indices[3 * t + 2] = indices[3 * t];  // a repeated vertex
      flags[t] = uint8_t(rng() % 4);
    }
    // Uneven batches, at an offset, as the rasterizer's chunks make them.
    const auto setUp = [&](auto function, std::vector<ScreenTriangle>& out, std::vector<TriangleSetUp>& status,
                           const uint8_t* triangleFlags, uint8_t uniformFlags) {
      size_t made = 0;
      for (size_t first = 0; first < kTriangles; first += 333) {
        const size_t count = std::min<size_t>(333, kTriangles - first);
        made += function(vertices.data(), indices.data(), triangleFlags, uniformFlags, uint32_t(first), count, size.x,
                         size.y, out.data() + made, status.data() + first);
      }
      out.resize(made);
    };
    // Per-triangle flags, and one mask for all: none, or back faces culled and alpha tested.
    const std::pair<const uint8_t*, uint8_t> flagCases[] = {
        {flags.data(), 0}, {nullptr, 0}, {nullptr, uint8_t(kTriangleCullBackFace | kTriangleAlphaTested)}};
    for (const auto& [triangleFlags, uniformFlags] : flagCases) {
      CAPTURE(triangleFlags != nullptr, int(uniformFlags));
      std::vector<ScreenTriangle> expected(kTriangles);
      std::vector<TriangleSetUp> expectedStatus(kTriangles);
      setUp(SetUpTrianglesScalar, expected, expectedStatus, triangleFlags, uniformFlags);
      size_t statusCount[3] = {};
      for (const TriangleSetUp status : expectedStatus) ++statusCount[size_t(status)];
      CHECK(statusCount[size_t(TriangleSetUp::kSetUp)] > kTriangles / 10);
      CHECK(statusCount[size_t(TriangleSetUp::kCulled)] > kTriangles / 100);
      CHECK(statusCount[size_t(TriangleSetUp::kClip)] > kTriangles / 10);
      // Small ones, bounds of a few pixels.
      CHECK(std::count_if(expected.begin(), expected.end(), [](const ScreenTriangle& t) {
              return t.maxX - t.minX < 4 && t.maxY - t.minY < 4;
            }) > std::ptrdiff_t(kTriangles / 50));
      const size_t targets = test::ForEachSimdTarget([&](const char* target) {
        std::vector<ScreenTriangle> actual(kTriangles);
        std::vector<TriangleSetUp> actualStatus(kTriangles);
        setUp(SetUpTrianglesSimd, actual, actualStatus, triangleFlags, uniformFlags);
        REQUIRE(actualStatus == expectedStatus);
        REQUIRE(actual.size() == expected.size());
        for (size_t t = 0; t < expected.size(); ++t) {
          CAPTURE(target, t);
          const ScreenTriangle &a = actual[t], &e = expected[t];
          REQUIRE(std::memcmp(a.x, e.x, sizeof(a.x)) == 0);
          REQUIRE(std::memcmp(a.y, e.y, sizeof(a.y)) == 0);
          REQUIRE((a.minX == e.minX && a.minY == e.minY && a.maxX == e.maxX && a.maxY == e.maxY));
          REQUIRE(std::memcmp(&a.keyAtOrigin, &e.keyAtOrigin, sizeof(double)) == 0);
          REQUIRE(std::memcmp(&a.keyDx, &e.keyDx, sizeof(double)) == 0);
          REQUIRE(std::memcmp(&a.keyDy, &e.keyDy, sizeof(double)) == 0);
          REQUIRE((a.triangle == e.triangle && a.flags == e.flags && a.edgesFit32Bits == e.edgesFit32Bits));
        }
      });
      CHECK(targets >= 2);
    }
  }
}

}  // namespace
}  // namespace ssgi
