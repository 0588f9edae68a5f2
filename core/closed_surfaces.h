// Closed surfaces of a mesh (docs/pipeline.md §Shadow map and blocker search): the connected parts
// whose every edge is shared by exactly two triangles that run along it in opposite directions, so
// the part encloses a volume with its front faces outside. Seen from outside, the nearest of its
// surfaces along any ray is a front face, so a depth-only raster from a viewpoint outside may cull
// its back faces and keep the same nearest depths.
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>
#include <vector>

#include "core/mesh.h"

namespace ssgi {

struct ClosedSurfaces {
  static constexpr uint32_t kOpen = std::numeric_limits<uint32_t>::max();
  // Per triangle: the index of its closed surface, or kOpen.
  std::vector<uint32_t> surface;
  // Per closed surface: the world-space box of its vertices.
  std::vector<glm::vec3> lo, hi;
  uint64_t meshHash = 0;  // MeshGeometryHash of the mesh they were found in
};

// Triangles are connected where they share an edge, their corners joined by equal positions (the
// same bits; an OBJ splits a vertex where its normal or UV changes). A part is closed when every
// edge has exactly two triangles, traversing it in opposite directions, no triangle has two corners
// at one position, and its signed volume is positive (front faces outside).
ClosedSurfaces FindClosedSurfaces(const Mesh& mesh);

// What FindClosedSurfaces holds at most while it works on a mesh of `triangles` triangles and
// `vertices` vertices, its result included.
size_t ClosedSurfacesBuildBytes(size_t triangles, size_t vertices);

}  // namespace ssgi
