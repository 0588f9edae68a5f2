#include "core/reference/ray_tracer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "core/brdf.h"
#include "core/surface.h"
#include "core/texture.h"

namespace ssgi {
namespace {

float AlphaChannel(const Texture& texture, const glm::vec4& texel) {
  // As the rasterizer's alpha test: grey+alpha and RGBA carry the mask in alpha, others in channel 0.
  return texture.sourceChannels == 2 || texture.sourceChannels == 4 ? texel.w : texel.x;
}

glm::vec2 InterpolateUv(const Mesh& mesh, const uint32_t* idx, float u, float v) {
  const glm::vec2 uv0 = mesh.uvs[idx[0]];
  return uv0 + (mesh.uvs[idx[1]] - uv0) * u + (mesh.uvs[idx[2]] - uv0) * v;
}

// Rejects a candidate hit on a cut-out texel, and for camera rays on a culled back face. Embree
// then continues the traversal past it, so the closest accepted hit wins whatever the BVH order.
void FilterHits(const RTCFilterFunctionNArguments* args) {
  const auto* context = reinterpret_cast<const TraceContext*>(args->context);
  const Scene& scene = *context->scene;
  for (unsigned int i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const uint32_t triangle = RTCHitN_primID(args->hit, args->N, i);
    const uint32_t* idx = &scene.mesh.indices[3 * size_t(triangle)];
    const Material& material = scene.materials[scene.mesh.materials[triangle]];
    if (context->kind == RayKind::kCamera && !material.twoSided) {
      const glm::vec3 direction(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                                RTCRayN_dir_z(args->ray, args->N, i));
      if (glm::dot(FaceNormal(scene.mesh, idx), direction) > 0.0f) {
        args->valid[i] = 0;
        continue;
      }
    }
    if (material.alphaTexture != kNoTexture) {
      const Texture& texture = scene.textures[material.alphaTexture];
      const glm::vec2 uv =
          InterpolateUv(scene.mesh, idx, RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i));
      if (AlphaChannel(texture, SampleTexture(texture, uv, 0.0f)) < material.alphaCutoff) args->valid[i] = 0;
    }
  }
}

}  // namespace

glm::vec3 FaceNormal(const Mesh& mesh, const uint32_t* idx) {
  const glm::vec3& p0 = mesh.positions[idx[0]];
  return glm::cross(mesh.positions[idx[1]] - p0, mesh.positions[idx[2]] - p0);
}

RayTracer::RayTracer(const Scene& scene) : scene_(scene) {
  device_ = rtcNewDevice(nullptr);
  if (device_ == nullptr) throw std::runtime_error("Embree: cannot create a device");
  // Embree reports every allocation and free of its device: the memory the scene's BVH takes.
  rtcSetDeviceMemoryMonitorFunction(
      device_,
      [](void* user, ssize_t bytes, bool) {
        auto* counter = static_cast<MemoryCounter*>(user);
        const ssize_t now = counter->now.fetch_add(bytes) + bytes;
        for (ssize_t peak = counter->peak.load(); now > peak && !counter->peak.compare_exchange_weak(peak, now);) {
        }
        return true;
      },
      &memory_);
  embreeScene_ = rtcNewScene(device_);
  // Robust mode: watertight traversal, no ray slipping through a shared edge.
  rtcSetSceneFlags(embreeScene_, RTC_SCENE_FLAG_ROBUST);
  const Mesh& mesh = scene.mesh;
  if (mesh.TriangleCount() > 0) {
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree's own buffers, over-allocated for its 16-byte vertex loads (a packed
    // std::vector<glm::vec3> shared in place would be read past its end).
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), mesh.positions.size()));
    auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(uint32_t), mesh.TriangleCount()));
    if (vertices == nullptr || indices == nullptr) throw std::runtime_error("Embree: cannot allocate the mesh");
    std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
    std::memcpy(indices, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
    rtcSetGeometryIntersectFilterFunction(geometry, &FilterHits);
    rtcSetGeometryOccludedFilterFunction(geometry, &FilterHits);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(embreeScene_, geometry);
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(embreeScene_);
  const RTCError error = rtcGetDeviceError(device_);
  if (error != RTC_ERROR_NONE) {
    rtcReleaseScene(embreeScene_);
    rtcReleaseDevice(device_);
    throw std::runtime_error("Embree: building the scene failed (error " + std::to_string(int(error)) + ")");
  }
}

// As passes/gbuffer.cpp's resolve, with Embree's barycentrics and texture level 0 (a ray has no
// pixel footprint, and the reference wants the texels themselves).
RaySurface ResolveRaySurface(const Scene& scene, const Hit& hit, const glm::vec3& rayDirection) {
  const Mesh& mesh = scene.mesh;
  const uint32_t* idx = &mesh.indices[3 * size_t(hit.triangle)];
  const float w0 = 1.0f - hit.u - hit.v;
  RaySurface s;
  s.position = mesh.positions[idx[0]] * w0 + mesh.positions[idx[1]] * hit.u + mesh.positions[idx[2]] * hit.v;
  glm::vec3 faceNormal = FaceNormal(mesh, idx);
  const float faceLength = glm::length(faceNormal);
  // Embree reports no hit on a zero-area triangle, so faceLength > 0; the guard keeps NaN out anyway.
  faceNormal = faceLength > 0.0f ? faceNormal / faceLength : glm::vec3(0.0f, 1.0f, 0.0f);
  glm::vec3 normal = mesh.normals[idx[0]] * w0 + mesh.normals[idx[1]] * hit.u + mesh.normals[idx[2]] * hit.v;
  const Material& material = scene.materials[mesh.materials[hit.triangle]];
  const glm::vec2 uv = InterpolateUv(mesh, idx, hit.u, hit.v);
  if (material.normalTexture != kNoTexture)
    normal = NormalMapped(scene, material, idx, glm::vec3(w0, hit.u, hit.v), normal, uv, 0.0f).normal;
  const float length = glm::length(normal);
  normal = length > 0.0f && std::isfinite(length) ? normal / length : faceNormal;
  // A two-sided surface seen from behind shades with the side that faces the ray.
  if (glm::dot(faceNormal, rayDirection) > 0.0f) {
    normal = -normal;
    faceNormal = -faceNormal;
  }
  s.normal = normal;
  s.faceNormal = faceNormal;

  s.material = {material.baseColor, material.metallic, material.roughness};
  if (material.vertexColors) s.material.albedo *= InterpolatedColor(mesh, idx, glm::vec3(w0, hit.u, hit.v));
  if (material.baseColorTexture != kNoTexture)
    s.material.albedo *= glm::vec3(SampleTexture(scene.textures[material.baseColorTexture], uv, 0.0f));
  if (material.metallicTexture != kNoTexture)
    s.material.metallic *= SampleTexture(scene.textures[material.metallicTexture], uv, 0.0f).x;
  if (material.roughnessTexture != kNoTexture)
    s.material.roughness *= SampleTexture(scene.textures[material.roughnessTexture], uv, 0.0f).x;
  s.alpha = std::max(s.material.roughness * s.material.roughness, kMinGgxAlpha);
  return s;
}

// How far a secondary ray starts off its surface: in proportion to the scene's extent, so float
// positions a long way from the origin do not hit their own triangle.
float RayOffset(const Scene& scene) {
  float extent = 0.0f;
  for (const glm::vec3& p : scene.mesh.positions)
    extent = std::max(extent, std::max(std::fabs(p.x), std::max(std::fabs(p.y), std::fabs(p.z))));
  return kRayOffsetScale * std::max(extent, 1.0f);
}

}  // namespace ssgi
