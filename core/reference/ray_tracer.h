// Embree 3 over the scene's mesh, for what traces rays through the scene: the reference
// (core/reference/reference.h) and the world-space bounce volume (passes/world_bounce.h). The mesh is
// one triangle geometry, primitive i being triangle i; hits resolve to the surface the G-buffer
// resolve would give (materials, textures at level 0, normal maps).
#pragma once

#include <embree3/rtcore.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>

#include "core/brdf.h"
#include "core/scene.h"

namespace ssgi {

// Secondary rays start this far (times the scene's largest coordinate) off the surface, along its
// geometric normal: about 80 float ulps of that coordinate, far above the rounding of a hit
// position rebuilt from barycentrics, far below any feature a scene models.
inline constexpr float kRayOffsetScale = 1e-5f;

// kCamera rays see what a camera sees (single-sided back faces are invisible, as the rasterizer
// culls them): primary rays, and the paper transport's bounce rays. kBothFaces rays are stopped by
// both faces of every surface: shadow rays (as the shadow map draws both), and every ray after the
// first in the full transport (a surface is opaque from either side). Both skip alpha cut-out
// holes.
enum class RayKind { kCamera, kBothFaces };

// Embree hands the filter the context pointer it was given, so the context carries what the
// filter needs (Embree 3 manual, "rtcInitIntersectContext": the context may be extended).
struct TraceContext {
  RTCIntersectContext embree;  // first member: a TraceContext* is a valid RTCIntersectContext*
  const Scene* scene;
  RayKind kind;
};

struct Hit {
  uint32_t triangle;
  float u, v;  // Embree's barycentrics: weights (1 - u - v, u, v) of the triangle's vertices
  float t;     // in units of the ray direction's length
};

// One Embree device and scene holding the scene's mesh as one triangle geometry, primitive i being
// triangle i of the mesh.
class RayTracer {
 public:
  explicit RayTracer(const Scene& scene);
  ~RayTracer() {
    rtcReleaseScene(embreeScene_);
    rtcReleaseDevice(device_);
  }
  RayTracer(const RayTracer&) = delete;
  RayTracer& operator=(const RayTracer&) = delete;

  // The most memory the device has held: the BVH and the mesh's copy.
  size_t PeakBytes() const { return size_t(std::max<ssize_t>(memory_.peak.load(), 0)); }

  // The closest accepted hit with t in [tnear, tfar]; false when there is none.
  bool Intersect(RayKind kind, const glm::vec3& origin, const glm::vec3& direction, float tnear, float tfar,
                 Hit& hit) const {
    RTCRayHit rayHit{};
    SetRay(rayHit.ray, origin, direction, tnear, tfar);
    rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    TraceContext context = MakeContext(kind);
    rtcIntersect1(embreeScene_, &context.embree, &rayHit);
    if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit = {rayHit.hit.primID, rayHit.hit.u, rayHit.hit.v, rayHit.ray.tfar};
    return true;
  }

  // Whether any surface stopping kBothFaces rays lies on the shadow ray with t in [tnear, tfar].
  bool Occluded(const glm::vec3& origin, const glm::vec3& direction, float tnear, float tfar) const {
    RTCRay ray{};
    SetRay(ray, origin, direction, tnear, tfar);
    TraceContext context = MakeContext(RayKind::kBothFaces);
    rtcOccluded1(embreeScene_, &context.embree, &ray);
    return ray.tfar < 0.0f;  // Embree sets tfar to -inf on an occluded ray
  }

 private:
  static void SetRay(RTCRay& ray, const glm::vec3& origin, const glm::vec3& direction, float tnear, float tfar) {
    ray.org_x = origin.x;
    ray.org_y = origin.y;
    ray.org_z = origin.z;
    ray.dir_x = direction.x;
    ray.dir_y = direction.y;
    ray.dir_z = direction.z;
    ray.tnear = tnear;
    ray.tfar = tfar;
    ray.mask = 0xFFFFFFFFu;
  }
  TraceContext MakeContext(RayKind kind) const {
    TraceContext context;
    rtcInitIntersectContext(&context.embree);
    context.scene = &scene_;
    context.kind = kind;
    return context;
  }

  const Scene& scene_;
  struct MemoryCounter {
    std::atomic<ssize_t> now{0}, peak{0};
  };
  MemoryCounter memory_;  // before device_: Embree reports into it until the device is released
  RTCDevice device_ = nullptr;
  RTCScene embreeScene_ = nullptr;
};

// The triangle's geometric normal, unnormalised: (p1 - p0) x (p2 - p0) of its indices `idx`.
glm::vec3 FaceNormal(const Mesh& mesh, const uint32_t* idx);

// A shaded point: what the G-buffer resolve computes, unquantised and in world space.
struct RaySurface {
  glm::vec3 position;
  glm::vec3 normal;      // unit shading normal, on the side the ray came from
  glm::vec3 faceNormal;  // unit geometric normal, on the side the ray came from
  SurfaceMaterial material;
  float alpha;  // GGX alpha, roughness^2 clamped to kMinGgxAlpha
};

// As passes/gbuffer.cpp's resolve, with Embree's barycentrics and texture level 0 (a ray has no
// pixel footprint, and the reference wants the texels themselves).
RaySurface ResolveRaySurface(const Scene& scene, const Hit& hit, const glm::vec3& rayDirection);

// How far a secondary ray starts off its surface: in proportion to the scene's extent, so float
// positions a long way from the origin do not hit their own triangle.
float RayOffset(const Scene& scene);

}  // namespace ssgi
