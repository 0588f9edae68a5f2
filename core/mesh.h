// Triangle meshes in world space. A scene bakes every object (OBJ x transform) into one Mesh, so the
// rasterizer and the Embree reference see the same triangles in the same order.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace ssgi {

struct Mesh {
  std::vector<glm::vec3> positions;  // world space, metres, all finite
  std::vector<glm::vec3> normals;    // world space, unit length, one per position
  std::vector<glm::vec2> uvs;        // one per position ((0, 0) where the OBJ has none)
  std::vector<uint32_t> indices;     // three per triangle, counter-clockwise front faces
  std::vector<uint32_t> materials;   // one per triangle, index into Scene::materials
  // Empty, or one per position: the unit tangent in world space (xyz) and the bitangent's sign (w),
  // bitangent = w * cross(normal, tangent) (MikkTSpace's convention). Read where a material has a
  // normal texture.
  std::vector<glm::vec4> tangents;
  // Empty, or one per position: linear RGB that multiplies the base colour (glTF's COLOR_0), read
  // where a material has vertexColors.
  std::vector<glm::vec3> colors;

  size_t TriangleCount() const { return materials.size(); }
};

// A hash of the positions and indices: where it is unchanged, so is everything made from the
// geometry alone (the sky visibility volume, the closed surfaces).
uint64_t MeshGeometryHash(const Mesh& mesh);

}  // namespace ssgi
