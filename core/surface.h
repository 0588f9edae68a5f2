// Surface interpolation of the scene's mesh as seen from one view (docs/pipeline.md §G-buffer): the
// barycentrics of a pixel's view ray on the plane of a visible triangle, the UV there and the UV
// footprint of the neighbouring pixels' rays, which picks the texture's mip level. Shared by the
// G-buffer resolve and the alpha test of the rasterizer's input (core/raster/scene_raster_input.h), so a
// cut-out is tested at exactly the surface point the resolve shades.
#pragma once

#include <cstdint>
#include <memory>

#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/scene.h"

namespace ssgi {

// What the resolve and the alpha test need of one visible point of a triangle.
struct SurfacePoint {
  glm::vec3 weights;  // barycentric weights of the triangle's three vertices, in [0, 1], sum 1
  glm::vec2 uv;
  float uvFootprint;  // larger UV step to the next pixel right or down
  // The barycentrics' (b1, b2) steps to the rays of the next pixel right and down, on the triangle's
  // plane (unclamped): the attributes' derivatives per pixel. 0 where a ray misses the plane.
  glm::vec2 baryStepX, baryStepY;
};

// The normal-mapped normal (docs/pipeline.md §G-buffer, "Normal mapping") of a point of the triangle
// with corners `idx` at barycentric `weights`, for a material with a normal texture: the texel at
// `uv` (SampleNormalTexture at `footprint`) as a tangent-space normal with x and y scaled by normalScale, in
// the frame of the interpolated, unnormalised tangent and `normal` (the interpolated vertex normal,
// in the mesh's space) with MikkTSpace's per-pixel bitangent w0 cross(normal, tangent). Not
// normalised.
struct MappedNormal {
  glm::vec3 normal;
  // The texels' normal lengths |s * 2 - 1| (before normalScale) filtered as the texel
  // (SampleNormalTexture): below 1 where a coarse level averaged normals that disagree (Toksvig 2005).
  float texelLength;
};
MappedNormal NormalMapped(const Scene& scene, const Material& material, const uint32_t* idx, const glm::vec3& weights,
                          const glm::vec3& normal, glm::vec2 uv, float footprint);

// The mesh's vertex colours interpolated at `weights` (for a material with vertexColors).
inline glm::vec3 InterpolatedColor(const Mesh& mesh, const uint32_t* idx, const glm::vec3& weights) {
  return mesh.colors[idx[0]] * weights.x + mesh.colors[idx[1]] * weights.y + mesh.colors[idx[2]] * weights.z;
}

// Holds the mesh's vertices in `view`'s view space (computed once, in parallel); both references
// must outlive it.
class SurfaceResolver {
 public:
  SurfaceResolver(const Scene& scene, const ViewProjection& view);

  const glm::vec3& ViewPosition(uint32_t vertex) const { return viewPositions_[vertex]; }
  const glm::vec3* ViewPositions() const { return viewPositions_.get(); }

  // The surface point of `triangle` under the centre of pixel (px, py), which the triangle covers.
  // uvFootprint and the barycentric steps are 0 unless `withSteps` (texture lookups and specular
  // anti-aliasing need them, the rest of the shading does not).
  SurfacePoint At(uint32_t triangle, int px, int py, bool withSteps) const;

 private:
  const Scene& scene_;
  const ViewProjection& view_;
  // Written in full, in parallel: not zeroed first (a one-thread memset of 6 MB for a million triangles).
  std::unique_ptr<glm::vec3[]> viewPositions_;
};

}  // namespace ssgi
