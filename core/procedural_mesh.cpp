#include "core/procedural_mesh.h"

#include <cmath>
#include <numbers>

#include "core/check.h"

namespace ssgi {

Mesh MakeTorusKnot(int tubularSegments, int radialSegments, const TorusKnotDesc& desc) {
  SSGI_CHECK_GE(tubularSegments, 3);
  SSGI_CHECK_GE(radialSegments, 3);
  SSGI_CHECK_LT(2.0 * double(tubularSegments) * double(radialSegments), 2147483648.0);
  SSGI_CHECK_GT(desc.p, 0);
  SSGI_CHECK_GT(desc.q, 0);

  const size_t rowLength = size_t(radialSegments) + 1;
  const size_t vertexCount = (size_t(tubularSegments) + 1) * rowLength;
  Mesh mesh;
  mesh.positions.resize(vertexCount);
  mesh.normals.resize(vertexCount);
  mesh.uvs.resize(vertexCount);

  const double radius = desc.radius, tube = desc.tubeRadius;
  const double p = desc.p, q = desc.q;
  const double twoPi = 2.0 * std::numbers::pi;
  for (int i = 0; i <= tubularSegments; ++i) {
    // The closing ring repeats the first one bit for bit, so the seam is watertight after snapping.
    const int source = i == tubularSegments ? 0 : i;
    const double u = twoPi * p * double(source) / double(tubularSegments);
    const double phase = q / p * u;
    const double cu = std::cos(u), su = std::sin(u), cp = std::cos(phase), sp = std::sin(phase);
    const glm::dvec3 centre = 0.5 * radius * glm::dvec3((2.0 + cp) * cu, (2.0 + cp) * su, sp);
    const glm::dvec3 tangent = glm::normalize(glm::dvec3(-q / p * sp * cu - (2.0 + cp) * su,
                                                         -q / p * sp * su + (2.0 + cp) * cu, q / p * cp));
    // The centre's position vector is never parallel to the tangent (its radial part is at least
    // radius / 2, the tangent's angular part at least 1 / |derivative|), so this frame never
    // degenerates; being a function of u alone, it also closes without a twist.
    const glm::dvec3 binormal = glm::normalize(glm::cross(tangent, centre));
    const glm::dvec3 normal = glm::cross(binormal, tangent);
    for (int j = 0; j <= radialSegments; ++j) {
      const int around = j == radialSegments ? 0 : j;
      const double v = twoPi * double(around) / double(radialSegments);
      const glm::dvec3 outward = std::cos(v) * normal + std::sin(v) * binormal;
      const size_t k = size_t(i) * rowLength + size_t(j);
      mesh.positions[k] = glm::vec3(centre + tube * outward);
      mesh.normals[k] = glm::vec3(glm::normalize(outward));
      mesh.uvs[k] = glm::vec2(float(double(i) / tubularSegments), float(double(j) / radialSegments));
    }
  }

  const size_t triangleCount = 2 * size_t(tubularSegments) * size_t(radialSegments);
  mesh.indices.reserve(3 * triangleCount);
  for (int i = 0; i < tubularSegments; ++i) {
    for (int j = 0; j < radialSegments; ++j) {
      const uint32_t a = uint32_t(size_t(i) * rowLength + size_t(j));
      const uint32_t b = a + uint32_t(rowLength);  // next along the knot
      const uint32_t d = a + 1;                    // next around the tube
      const uint32_t c = b + 1;
      // (d - a) x (b - a) points along the outward normal: around-the-tube x along-the-knot.
      mesh.indices.insert(mesh.indices.end(), {a, d, b, b, d, c});
    }
  }
  mesh.materials.assign(triangleCount, 0u);
  return mesh;
}

void AddQuad(Mesh& mesh, glm::vec3 o, glm::vec3 u, glm::vec3 v, uint32_t material) {
  const uint32_t base = uint32_t(mesh.positions.size());
  const glm::vec3 normal = glm::normalize(glm::cross(u, v));
  for (const glm::vec3& p : {o, o + u, o + u + v, o + v}) {
    mesh.positions.push_back(p);
    mesh.normals.push_back(normal);
    mesh.uvs.push_back(glm::vec2(0.0f));
  }
  mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  mesh.materials.insert(mesh.materials.end(), {material, material});
}

void AddBox(Mesh& mesh, glm::vec3 lo, glm::vec3 hi, uint32_t material) {
  const glm::vec3 d = hi - lo;
  const glm::vec3 x(d.x, 0, 0), y(0, d.y, 0), z(0, 0, d.z);
  AddQuad(mesh, lo, x, z, material);      // bottom, -y
  AddQuad(mesh, lo + y, z, x, material);  // top, +y
  AddQuad(mesh, lo, y, x, material);      // back, -z
  AddQuad(mesh, lo + z, x, y, material);  // front, +z
  AddQuad(mesh, lo, z, y, material);      // left, -x
  AddQuad(mesh, lo + x, y, z, material);  // right, +x
}

}  // namespace ssgi
