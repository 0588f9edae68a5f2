#include "core/surface.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"

namespace ssgi {
namespace {

// Barycentrics (b1, b2) of the point where a ray meets the plane of (p0, p1, p2), not limited to
// the triangle (Moller-Trumbore without the bounds test). False when the ray is parallel to it.
bool RayPlaneBarycentrics(const ViewProjection::Ray& ray, const glm::vec3& p0, const glm::vec3& e1,
                          const glm::vec3& e2, glm::vec2& b) {
  const glm::vec3 p = glm::cross(ray.direction, e2);
  const float det = glm::dot(e1, p);
  if (!(std::fabs(det) > 1e-30f)) return false;
  const float invDet = 1.0f / det;
  const glm::vec3 s = ray.origin - p0;
  const glm::vec3 q = glm::cross(s, e1);
  b = {glm::dot(s, p) * invDet, glm::dot(ray.direction, q) * invDet};
  return std::isfinite(b.x) && std::isfinite(b.y);
}

}  // namespace

MappedNormal NormalMapped(const Scene& scene, const Material& material, const uint32_t* idx, const glm::vec3& weights,
                          const glm::vec3& normal, glm::vec2 uv, float footprint) {
  const std::vector<glm::vec4>& tangents = scene.mesh.tangents;
  const glm::vec3 tangent = glm::vec3(tangents[idx[0]]) * weights.x + glm::vec3(tangents[idx[1]]) * weights.y +
                            glm::vec3(tangents[idx[2]]) * weights.z;
  const glm::vec3 bitangent = glm::cross(normal, tangent) * tangents[idx[0]].w;
  const glm::vec4 texel = SampleNormalTexture(scene.textures[material.normalTexture], uv, footprint);
  const float mx = (texel.x * 2.0f - 1.0f) * material.normalScale;
  const float my = (texel.y * 2.0f - 1.0f) * material.normalScale;
  const float mz = texel.z * 2.0f - 1.0f;
  return {tangent * mx + bitangent * my + normal * mz, texel.w};
}

SurfaceResolver::SurfaceResolver(const Scene& scene, const ViewProjection& view) : scene_(scene), view_(view) {
  const Mesh& mesh = scene.mesh;
  viewPositions_ = std::make_unique_for_overwrite<glm::vec3[]>(mesh.positions.size());
  constexpr size_t kChunk = 16384;
  ParallelFor("surface.view_positions", (mesh.positions.size() + kChunk - 1) / kChunk, [&](size_t c) {
    const size_t end = std::min(mesh.positions.size(), (c + 1) * kChunk);
    for (size_t i = c * kChunk; i < end; ++i)
      viewPositions_[i] = glm::vec3(view.view * glm::vec4(mesh.positions[i], 1.0f));
  });
}

SurfacePoint SurfaceResolver::At(uint32_t triangle, int px, int py, bool withSteps) const {
  const uint32_t* idx = &scene_.mesh.indices[3 * size_t(triangle)];
  const glm::vec3& p0 = viewPositions_[idx[0]];
  const glm::vec3 e1 = viewPositions_[idx[1]] - p0;
  const glm::vec3 e2 = viewPositions_[idx[2]] - p0;
  const float cx = float(px) + 0.5f, cy = float(py) + 0.5f;
  glm::vec2 center(1.0f / 3.0f);
  const bool hit = RayPlaneBarycentrics(view_.PixelRay(cx, cy), p0, e1, e2, center);
  // The pixel centre is inside the snapped triangle, so b leaves [0, 1] only by rounding and
  // snapping; clamping keeps attributes from extrapolating on slivers.
  glm::vec2 b = glm::clamp(center, 0.0f, 1.0f);
  if (b.x + b.y > 1.0f) b /= (b.x + b.y);
  SurfacePoint s;
  s.weights = {1.0f - b.x - b.y, b.x, b.y};
  const std::vector<glm::vec2>& uvs = scene_.mesh.uvs;
  const glm::vec2 uv0 = uvs[idx[0]], du1 = uvs[idx[1]] - uv0, du2 = uvs[idx[2]] - uv0;
  s.uv = uv0 + du1 * b.x + du2 * b.y;
  s.uvFootprint = 0.0f;
  s.baryStepX = s.baryStepY = glm::vec2(0.0f);
  glm::vec2 bx, by;
  // Unclamped here: the steps are derivatives of the plane's parameterisation.
  if (withSteps && hit) {
    if (RayPlaneBarycentrics(view_.PixelRay(cx + 1.0f, cy), p0, e1, e2, bx) &&
        RayPlaneBarycentrics(view_.PixelRay(cx, cy + 1.0f), p0, e1, e2, by)) {
      s.baryStepX = bx - center;
      s.baryStepY = by - center;
      const glm::vec2 ddx = du1 * s.baryStepX.x + du2 * s.baryStepX.y;
      const glm::vec2 ddy = du1 * s.baryStepY.x + du2 * s.baryStepY.y;
      const float footprint = std::max(glm::length(ddx), glm::length(ddy));
      s.uvFootprint = std::isfinite(footprint) ? footprint : 0.0f;
    }
  }
  return s;
}

}  // namespace ssgi
