// Procedural meshes for tests and benchmarks: geometry whose size is a parameter, so the rasterizer
// can be checked against Embree and timed from a few thousand triangles up to millions without
// shipping large model files.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "core/mesh.h"

namespace ssgi {

struct TorusKnotDesc {
  float radius = 1.0f;      // metres; the knot's centre curve stays within 1.5 * radius of the origin
  float tubeRadius = 0.3f;  // metres; the p = 2, q = 3 strands come within 0.653 * radius of each
                            // other, so the tube does not intersect itself below 0.32 * radius
  int p = 2;                // windings around the symmetry axis (z); coprime with q
  int q = 3;                // windings through the hole
};

// A (p, q) torus knot tube around the origin (the three.js TorusKnotGeometry curve, symmetry axis z):
// a closed, watertight mesh that occludes itself and shows silhouettes from any direction.
//  - 2 * tubularSegments * radialSegments triangles (e.g. 2048 x 256 gives 1,048,576), counter-
//    clockwise seen from outside the tube; (tubularSegments + 1) * (radialSegments + 1) vertices.
//    Triangles [2 * radialSegments * i, 2 * radialSegments * (i + 1)) are the ring of segment i along
//    the knot, so a triangle index tells how far along the knot it lies.
//  - The seam vertices are bit-exact copies of the first row and column, so shared edges snap alike.
//  - normals: unit, analytic (away from the centre curve); uvs: u along the knot, v around the tube,
//    both in [0, 1]; materials: all 0.
//  - Deterministic: no randomness; the only libm calls are sin/cos/sqrt in double precision.
// Requires tubularSegments >= 3, radialSegments >= 3 and 2 * tubularSegments * radialSegments < 2^31.
Mesh MakeTorusKnot(int tubularSegments, int radialSegments, const TorusKnotDesc& desc = {});

// A quad o, o + u, o + u + v, o + v, counter-clockwise seen from the side cross(u, v) points to,
// with flat normals, UVs 0 and the material `material`.
void AddQuad(Mesh& mesh, glm::vec3 o, glm::vec3 u, glm::vec3 v, uint32_t material = 0);

// An axis-aligned box with outward faces and flat normals, all of the material `material`.
void AddBox(Mesh& mesh, glm::vec3 lo, glm::vec3 hi, uint32_t material = 0);

}  // namespace ssgi
