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

  size_t TriangleCount() const { return materials.size(); }
};

}  // namespace ssgi
