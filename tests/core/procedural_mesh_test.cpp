#include "core/procedural_mesh.h"

#include <cmath>
#include <map>
#include <tuple>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

namespace ssgi {
namespace {

TEST_CASE("torus knot is closed, consistently oriented and outward facing", "[procedural_mesh]") {
  const Mesh mesh = MakeTorusKnot(24, 6);
  REQUIRE(mesh.TriangleCount() == 2u * 24u * 6u);
  REQUIRE(mesh.indices.size() == 3 * mesh.TriangleCount());
  REQUIRE(mesh.normals.size() == mesh.positions.size());
  REQUIRE(mesh.uvs.size() == mesh.positions.size());
  for (uint32_t m : mesh.materials) REQUIRE(m == 0u);
  for (const glm::vec3& n : mesh.normals) REQUIRE(std::fabs(glm::length(n) - 1.0f) < 1e-6f);

  // Seam vertices repeat positions bit for bit: weld by position, then every directed edge must
  // appear once and its reverse once (closed, manifold, consistently wound).
  std::map<std::tuple<float, float, float>, uint32_t> weld;
  std::vector<uint32_t> welded(mesh.positions.size());
  for (uint32_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec3& p = mesh.positions[v];
    welded[v] = weld.try_emplace({p.x, p.y, p.z}, uint32_t(weld.size())).first->second;
  }
  REQUIRE(weld.size() == 24u * 6u);
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (size_t t = 0; t < mesh.TriangleCount(); ++t) {
    const uint32_t* idx = &mesh.indices[3 * t];
    for (int k = 0; k < 3; ++k) ++edges[{welded[idx[k]], welded[idx[(k + 1) % 3]]}];
    const glm::vec3 face = glm::cross(mesh.positions[idx[1]] - mesh.positions[idx[0]],
                                      mesh.positions[idx[2]] - mesh.positions[idx[0]]);
    const glm::vec3 vertexNormals = mesh.normals[idx[0]] + mesh.normals[idx[1]] + mesh.normals[idx[2]];
    REQUIRE(glm::dot(face, vertexNormals) > 0.0f);
  }
  for (const auto& [edge, count] : edges) {
    REQUIRE(count == 1);
    REQUIRE(edges.count({edge.second, edge.first}) == 1);
  }
}

}  // namespace
}  // namespace ssgi
