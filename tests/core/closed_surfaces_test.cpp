#include "core/closed_surfaces.h"

#include <catch2/catch.hpp>

#include "core/procedural_mesh.h"
#include "core/raster/scene_raster_input.h"

namespace ssgi {
namespace {

Mesh TwoBoxesAndAQuad() {
  Mesh mesh;
  AddBox(mesh, glm::vec3(-1.0f), glm::vec3(1.0f));
  AddQuad(mesh, glm::vec3(-4.0f, -1.0f, -4.0f), glm::vec3(0.0f, 0.0f, 8.0f), glm::vec3(8.0f, 0.0f, 0.0f));
  AddBox(mesh, glm::vec3(2.0f, 0.0f, 0.0f), glm::vec3(3.0f, 0.5f, 2.0f));
  return mesh;
}

// Every index of triangle t's corners, turned the other way round.
void Flip(Mesh& mesh, size_t t) { std::swap(mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]); }

TEST_CASE("closed surfaces: boxes whose faces share no vertex are closed, a quad is open", "[closed_surfaces]") {
  const Mesh mesh = TwoBoxesAndAQuad();
  const ClosedSurfaces closed = FindClosedSurfaces(mesh);
  REQUIRE(closed.surface.size() == mesh.TriangleCount());
  REQUIRE(closed.lo.size() == 2);
  for (size_t t = 0; t < 12; ++t) CHECK(closed.surface[t] == 0);
  CHECK(closed.surface[12] == ClosedSurfaces::kOpen);
  CHECK(closed.surface[13] == ClosedSurfaces::kOpen);
  for (size_t t = 14; t < 26; ++t) CHECK(closed.surface[t] == 1);
  CHECK(closed.lo[0] == glm::vec3(-1.0f));
  CHECK(closed.hi[0] == glm::vec3(1.0f));
  CHECK(closed.lo[1] == glm::vec3(2.0f, 0.0f, 0.0f));
  CHECK(closed.hi[1] == glm::vec3(3.0f, 0.5f, 2.0f));
  CHECK(closed.meshHash == MeshGeometryHash(mesh));
}

TEST_CASE("closed surfaces: a hole, a flipped face, an inside-out box, a fin and a degenerate triangle open a part",
          "[closed_surfaces]") {
  const auto firstBoxClosed = [](const Mesh& mesh) {
    return FindClosedSurfaces(mesh).surface[0] != ClosedSurfaces::kOpen;
  };
  Mesh mesh = TwoBoxesAndAQuad();
  REQUIRE(firstBoxClosed(mesh));
  SECTION("a face missing") {
    mesh.indices.erase(mesh.indices.begin() + 3 * 10, mesh.indices.begin() + 3 * 12);
    mesh.materials.erase(mesh.materials.begin() + 10, mesh.materials.begin() + 12);
  }
  SECTION("one face turned round: its edges run the same way as their neighbours'") {
    Flip(mesh, 4);
    Flip(mesh, 5);
  }
  SECTION("every face turned round: closed, but its front faces inside") {
    for (size_t t = 0; t < 12; ++t) Flip(mesh, t);
  }
  SECTION("a fin on an edge: three triangles share it") {
    const uint32_t base = uint32_t(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), {glm::vec3(-1.0f, -1.0f, -1.0f), glm::vec3(1.0f, -1.0f, -1.0f),
                                                 glm::vec3(0.0f, -3.0f, -1.0f)});
    mesh.normals.insert(mesh.normals.end(), 3, glm::vec3(0.0f, 0.0f, 1.0f));
    mesh.uvs.insert(mesh.uvs.end(), 3, glm::vec2(0.0f));
    mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2});
    mesh.materials.push_back(0);
  }
  SECTION("a triangle with two corners at one position") { mesh.indices[3 * 3 + 1] = mesh.indices[3 * 3]; }
  CHECK_FALSE(firstBoxClosed(mesh));
  CHECK(FindClosedSurfaces(mesh).lo.size() == 1);  // the other box
}

TEST_CASE("closed surfaces: a torus knot's tube is one closed surface", "[closed_surfaces]") {
  const Mesh knot = MakeTorusKnot(64, 8);
  const ClosedSurfaces closed = FindClosedSurfaces(knot);
  REQUIRE(closed.lo.size() == 1);
  for (uint32_t s : closed.surface) CHECK(s == 0);
}

TEST_CASE(
    "closed surfaces: a raster culls a box's back faces only from outside it, beyond the near plane and "
    "without cut-outs",
    "[closed_surfaces]") {
  Scene scene;
  scene.mesh = TwoBoxesAndAQuad();
  scene.materials.resize(2);
  const ClosedSurfaces closed = FindClosedSurfaces(scene.mesh);
  const auto culled = [&](glm::vec3 eye, float nearPlane, glm::vec3 target = glm::vec3(0.0f)) {
    CameraDesc desc;
    desc.position = eye;
    desc.target = target;
    desc.nearPlane = nearPlane;
    return CulledClosedSurfaces(scene, closed, MakePerspective(desc, 64, 64));
  };
  CHECK(culled(glm::vec3(0.0f, 8.0f, 1.0f), 0.05f) == std::vector<uint8_t>{1, 1});
  // Inside the first box, looking at the second.
  CHECK(culled(glm::vec3(-0.5f, 0.0f, 0.0f), 0.05f, glm::vec3(5.0f, 0.0f, 1.0f)) == std::vector<uint8_t>{0, 1});
  // The near plane cuts the first box (its top is 6.95 m away along the view, the second box's 7.32 m).
  CHECK(culled(glm::vec3(0.0f, 8.0f, 1.0f), 7.0f) == std::vector<uint8_t>{0, 1});
  // A cut-out on the second box.
  scene.materials[1].alphaTexture = 0;
  scene.mesh.materials[14] = 1;
  CHECK(culled(glm::vec3(0.0f, 8.0f, 1.0f), 0.05f) == std::vector<uint8_t>{1, 0});
}

}  // namespace
}  // namespace ssgi
