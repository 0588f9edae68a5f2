#include "core/raster/raster.h"

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "core/parallel.h"
#include "core/procedural_mesh.h"
#include "core/raster/scene_raster_input.h"

namespace ssgi {
namespace {

struct TestMesh {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
};

// A jittered grid of (n + 1)^2 shared vertices spanning [-extent, extent]^2 in the plane z = 0,
// split into counter-clockwise triangles along alternating diagonals: it tiles its square exactly.
TestMesh JitteredGrid(int n, float extent, uint32_t seed) {
  TestMesh mesh;
  std::mt19937 rng(seed);
  // At most 0.2 of a cell per axis: no triangle can fold over, so the mesh still tiles its square.
  std::uniform_real_distribution<float> jitter(-0.2f, 0.2f);
  const float step = 2.0f * extent / float(n);
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const bool border = i == 0 || j == 0 || i == n || j == n;
      const float jx = border ? 0.0f : jitter(rng) * step, jy = border ? 0.0f : jitter(rng) * step;
      mesh.positions.push_back({-extent + float(i) * step + jx, -extent + float(j) * step + jy, 0.0f});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
      if ((i + j) % 2 == 0) {
        mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
      } else {
        mesh.indices.insert(mesh.indices.end(), {a, b, c, b, d, c});
      }
    }
  }
  return mesh;
}

Plane<uint32_t> Coverage(const TestMesh& mesh, const ViewProjection& view) {
  RasterInput input;
  input.positions = mesh.positions.data();
  input.vertexCount = mesh.positions.size();
  input.indices = mesh.indices.data();
  input.triangleCount = mesh.indices.size() / 3;
  VisibilityBuffer target = MakeVisibilityBuffer(view.width, view.height, RasterOutput::kVisibility);
  Plane<uint32_t> coverage = MakePlane<uint32_t>(view.width, view.height, 0u);
  Rasterize(input, view, RasterOutput::kVisibility, target, &coverage);
  return coverage;
}

size_t CountNotOnce(const Plane<uint32_t>& coverage) {
  size_t bad = 0;
  for (size_t y = 0; y < coverage.ysize(); ++y)
    for (size_t x = 0; x < coverage.xsize(); ++x) bad += coverage.ConstRow(y)[x] != 1u;
  return bad;
}

// Cells of about 7 pixels, and of about 0.9: triangles smaller than a pixel, most covering one pixel
// centre or none (those the set-up culls), as a dense mesh gives.
TEST_CASE("a mesh tiling the screen covers every pixel exactly once", "[raster]") {
  const int width = 157, height = 101;  // odd, several tiles, partial edge tiles
  int configurations = 0;
  for (const int cells : {23, 180}) {
    for (float angle : {0.0f, 7.0f, 30.0f, 45.0f, 90.0f, 123.4f}) {
      for (float offset : {0.0f, 0.25f / 157.0f, 0.5f / 157.0f, 1.0f / 512.0f, 0.3333f / 157.0f}) {
        // Orthographic views whose pixel grid is rotated and shifted against the mesh.
        const glm::vec3 up(std::sin(glm::radians(angle)), std::cos(glm::radians(angle)), 0.0f);
        const glm::vec3 eye(offset, offset * 0.7f, 1.0f);
        const ViewProjection view =
            MakeOrthographic(eye, {0.0f, 0.0f, -1.0f}, up, 1.0f, 101.0f / 157.0f, 0.1f, 10.0f, width, height);
        const TestMesh mesh = JitteredGrid(cells, 2.0f, uint32_t(configurations));
        CAPTURE(cells, angle, offset);
        CHECK(CountNotOnce(Coverage(mesh, view)) == 0);
        ++configurations;
      }
    }
  }
  CHECK(configurations == 60);
}

TEST_CASE("a tilted mesh under perspective also tiles exactly once", "[raster]") {
  for (float tilt : {0.0f, 35.0f, 70.0f}) {
    CameraDesc camera;
    camera.position = {0.01f, 0.02f, 3.0f};
    camera.target = {0.0f, 0.0f, 0.0f};
    camera.fovYDegrees = 50.0f;
    const ViewProjection view = MakePerspective(camera, 130, 97);
    TestMesh mesh = JitteredGrid(40, 12.0f, 7);
    const glm::mat4 rotate = glm::rotate(glm::mat4(1.0f), glm::radians(tilt), glm::vec3(1.0f, 0.0f, 0.0f));
    for (glm::vec3& p : mesh.positions) p = glm::vec3(rotate * glm::vec4(p, 1.0f));
    // Tilted planes cross behind the camera: the near-plane clip must keep the tiling exact.
    const Plane<uint32_t> coverage = Coverage(mesh, view);
    size_t covered = 0, multiple = 0;
    for (size_t y = 0; y < coverage.ysize(); ++y) {
      for (size_t x = 0; x < coverage.xsize(); ++x) {
        covered += coverage.ConstRow(y)[x] > 0;
        multiple += coverage.ConstRow(y)[x] > 1;
      }
    }
    CAPTURE(tilt);
    CHECK(multiple == 0);
    if (tilt < 60.0f) CHECK(covered == coverage.xsize() * coverage.ysize());
  }
}

ViewProjection TestCamera(int width, int height) {
  CameraDesc camera;
  camera.position = {0.0f, 0.0f, 0.0f};
  camera.target = {0.0f, 0.0f, -1.0f};
  camera.fovYDegrees = 60.0f;
  camera.nearPlane = 0.1f;
  return MakePerspective(camera, width, height);
}

// Whether the view ray through a pixel centre meets the triangle beyond the near plane.
bool RayHits(const ViewProjection& view, const TestMesh& mesh, int x, int y) {
  const glm::vec3 dir = view.PixelRay(float(x) + 0.5f, float(y) + 0.5f).direction;
  const glm::vec3 p0 = mesh.positions[0], e1 = mesh.positions[1] - p0, e2 = mesh.positions[2] - p0;
  const glm::vec3 p = glm::cross(dir, e2);
  const float det = glm::dot(e1, p);
  const glm::vec3 s = -p0;
  const float u = glm::dot(s, p) / det;
  const glm::vec3 q = glm::cross(s, e1);
  const float v = glm::dot(dir, q) / det;
  const float t = glm::dot(e2, q) / det;  // view depth, since dir.z = -1
  return u >= 0.0f && v >= 0.0f && u + v <= 1.0f && t >= view.nearPlane;
}

TEST_CASE("near-plane clipping renders the visible part of a triangle crossing it", "[raster]") {
  const ViewProjection view = TestCamera(96, 64);
  // One vertex behind the camera (w < 0), two in front.
  const TestMesh mesh{{{-1.0f, -1.0f, -2.0f}, {1.0f, -1.0f, -2.0f}, {0.0f, 1.5f, 1.0f}}, {0, 1, 2}};
  RasterInput input{mesh.positions.data(), 3, mesh.indices.data(), 1, nullptr, {}};
  VisibilityBuffer target = MakeVisibilityBuffer(view.width, view.height, RasterOutput::kVisibility);
  const RasterStats stats = Rasterize(input, view, RasterOutput::kVisibility, target);
  CHECK(stats.trianglesClipped == 1);
  size_t covered = 0, disagreements = 0;
  for (int y = 0; y < view.height; ++y) {
    for (int x = 0; x < view.width; ++x) {
      const float key = target.depthKey.ConstRow(y)[x];
      REQUIRE(std::isfinite(key));
      REQUIRE(key >= 0.0f);
      REQUIRE(key <= 1.0f);
      const bool drawn = target.triangle.ConstRow(y)[x] == 0u;
      covered += drawn;
      disagreements += drawn != RayHits(view, mesh, x, y);
    }
  }
  CHECK(covered > 500);
  // Only pixels whose centre lies within snapping distance of an edge may disagree.
  CHECK(disagreements <= 4);
}

TEST_CASE("triangles behind the camera or on its plane draw nothing", "[raster]") {
  const ViewProjection view = TestCamera(64, 64);
  const TestMesh behind{{{-1.0f, -1.0f, 2.0f}, {1.0f, -1.0f, 2.0f}, {0.0f, 1.0f, 3.0f}}, {0, 1, 2}};
  const TestMesh onCameraPlane{{{-1.0f, -1.0f, 0.0f}, {1.0f, -1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}}, {0, 1, 2}};
  const TestMesh straddlingEye{{{-1.0f, 0.0f, 0.05f}, {1.0f, 0.0f, 0.05f}, {0.0f, 0.0f, -0.05f}}, {0, 1, 2}};
  for (const TestMesh* mesh : {&behind, &onCameraPlane, &straddlingEye}) {
    RasterInput input{mesh->positions.data(), 3, mesh->indices.data(), 1, nullptr, {}};
    VisibilityBuffer target = MakeVisibilityBuffer(64, 64, RasterOutput::kVisibility);
    Rasterize(input, view, RasterOutput::kVisibility, target);
    for (int y = 0; y < 64; ++y) {
      for (int x = 0; x < 64; ++x) {
        REQUIRE(target.triangle.ConstRow(y)[x] == kNoTriangle);
        REQUIRE(target.depthKey.ConstRow(y)[x] == 0.0f);
      }
    }
  }
}

TEST_CASE("back faces are culled only when asked, and the nearer surface wins", "[raster]") {
  const ViewProjection view = TestCamera(32, 32);
  // Two full-screen quads: the far one (first) faces the camera, the near one (second) faces away.
  TestMesh mesh;
  for (float z : {-5.0f, -2.0f}) {
    const uint32_t base = uint32_t(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), {{-9, -9, z}, {9, -9, z}, {9, 9, z}, {-9, 9, z}});
    if (z < -4.0f) {
      mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    } else {
      mesh.indices.insert(mesh.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
    }
  }
  for (const bool perTriangle : {true, false}) {  // the masks as an array, or one for all triangles
    for (const bool cull : {false, true}) {
      const uint8_t mask = cull ? uint8_t(kTriangleCullBackFace) : uint8_t(0);
      const std::vector<uint8_t> flags(4, mask);
      RasterInput input{mesh.positions.data(), mesh.positions.size(), mesh.indices.data(), 4, flags.data(), {}};
      if (!perTriangle) {
        input.triangleFlags = nullptr;
        input.uniformFlags = mask;
      }
      VisibilityBuffer target = MakeVisibilityBuffer(32, 32, RasterOutput::kVisibility);
      Rasterize(input, view, RasterOutput::kVisibility, target);
      const uint32_t id = target.triangle.ConstRow(16)[16];
      CAPTURE(perTriangle, cull);
      if (cull) {
        CHECK(id < 2u);
      } else {
        CHECK(id >= 2u);
      }
      CHECK(view.DepthFromKey(target.depthKey.ConstRow(16)[16]) == Approx(cull ? 5.0f : 2.0f).epsilon(1e-5));
    }
  }
}

// Through a scene's raster input, back faces are culled per material: a quad facing away from the
// camera on each half of the image, of a two-sided material and a one-sided one, or both of one kind
// (the input then gives one mask for every triangle).
TEST_CASE("a scene's raster input culls the back faces of one-sided materials only", "[raster]") {
  for (const bool leftTwoSided : {false, true}) {
    for (const bool rightTwoSided : {false, true}) {
      Scene scene;
      scene.camera.position = {0.0f, 0.0f, 3.0f};
      scene.camera.target = {0.0f, 0.0f, 0.0f};
      for (const bool twoSided : {leftTwoSided, rightTwoSided}) {
        Material material;
        material.twoSided = twoSided;
        scene.materials.push_back(material);
      }
      // u x v = -z: both face away from the camera.
      AddQuad(scene.mesh, {-2.0f, 2.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, -4.0f, 0.0f}, 0);
      AddQuad(scene.mesh, {0.0f, 2.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, -4.0f, 0.0f}, 1);
      const ViewProjection view = MakePerspective(scene.camera, 32, 32);
      const SceneRasterInput input(scene, view, true);
      CHECK((input.Get().triangleFlags == nullptr) == (leftTwoSided == rightTwoSided));
      VisibilityBuffer target = MakeVisibilityBuffer(32, 32, RasterOutput::kVisibility);
      Rasterize(input.Get(), view, RasterOutput::kVisibility, target);
      CAPTURE(leftTwoSided, rightTwoSided);
      CHECK((target.triangle.ConstRow(16)[8] != kNoTriangle) == leftTwoSided);
      CHECK((target.triangle.ConstRow(16)[24] != kNoTriangle) == rightTwoSided);
    }
  }
}

TEST_CASE("rasterization is identical at 1, 2 and 3 threads", "[raster][determinism]") {
  TestMesh mesh = JitteredGrid(120, 3.0f, 11);
  // Overlapping layers make the depth test and submission order matter.
  const size_t n = mesh.positions.size();
  for (size_t i = 0; i < n; ++i) mesh.positions.push_back(mesh.positions[i] * 0.8f + glm::vec3(0.1f, 0.0f, 0.4f * std::sin(float(i))));
  const size_t triangles = mesh.indices.size() / 3;
  for (size_t i = 0; i < triangles * 3; ++i) mesh.indices.push_back(mesh.indices[i] + uint32_t(n));
  CameraDesc camera;
  camera.position = {0.3f, 0.4f, 4.0f};
  const ViewProjection view = MakePerspective(camera, 211, 143);
  std::vector<std::vector<uint32_t>> results;
  for (int threads : {1, 2, 3}) {
    const ThreadLimit limit(threads);
    RasterInput input{mesh.positions.data(), mesh.positions.size(), mesh.indices.data(), mesh.indices.size() / 3, nullptr, {}};
    VisibilityBuffer target = MakeVisibilityBuffer(view.width, view.height, RasterOutput::kVisibility);
    Rasterize(input, view, RasterOutput::kVisibility, target);
    std::vector<uint32_t> bits;
    for (int y = 0; y < view.height; ++y) {
      for (int x = 0; x < view.width; ++x) {
        uint32_t keyBits;
        std::memcpy(&keyBits, &target.depthKey.ConstRow(y)[x], 4);
        bits.push_back(keyBits);
        bits.push_back(target.triangle.ConstRow(y)[x]);
      }
    }
    results.push_back(std::move(bits));
  }
  CHECK(results[0] == results[1]);
  CHECK(results[0] == results[2]);
}

}  // namespace
}  // namespace ssgi
