#include "core/reference/reference.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/brdf.h"
#include "core/camera.h"
#include "core/check.h"
#include "core/gbuffer.h"
#include "core/lighting.h"
#include "core/parallel.h"
#include "core/stopwatch.h"
#include "core/surface.h"

namespace ssgi {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
// Secondary rays start this far (times the scene's largest coordinate) off the surface, along its
// geometric normal: about 80 float ulps of that coordinate, far above the rounding of a hit
// position rebuilt from barycentrics, far below any feature a scene models.
constexpr float kRayOffsetScale = 1e-5f;

// PCG-XSH-RR 64/32 (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient Statistically Good
// Algorithms for Random Number Generation", pcg32_srandom_r / pcg32_random_r).
class Pcg32 {
 public:
  Pcg32(uint64_t seed, uint64_t stream) : increment_((stream << 1u) | 1u) {
    Next();
    state_ += seed;
    Next();
  }
  uint32_t Next() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + increment_;
    const uint32_t xorShifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const uint32_t rotation = uint32_t(old >> 59u);
    return (xorShifted >> rotation) | (xorShifted << ((32u - rotation) & 31u));
  }
  // Uniform in [0, 1): the top 24 bits, exactly representable.
  float Uniform() { return float(Next() >> 8) * 0x1p-24f; }

 private:
  uint64_t state_ = 0;
  uint64_t increment_;
};

// SplitMix64's finaliser (Steele et al. 2014): decorrelates the seeds of neighbouring pixels.
uint64_t Mix64(uint64_t x) {
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Orthonormal basis (t, b, n) around unit n (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited", JCGT 6(1)): branch-free apart from the sign of n.z, accurate near the poles.
struct Basis {
  glm::vec3 t, b, n;
  explicit Basis(const glm::vec3& normal) : n(normal) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float c = n.x * n.y * a;
    t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
  }
  glm::vec3 ToWorld(const glm::vec3& local) const { return t * local.x + b * local.y + n * local.z; }
  glm::vec3 ToLocal(const glm::vec3& world) const {
    return {glm::dot(world, t), glm::dot(world, b), glm::dot(world, n)};
  }
};

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

float AlphaChannel(const Texture& texture, const glm::vec4& texel) {
  // As the rasterizer's alpha test: grey+alpha and RGBA carry the mask in alpha, others in channel 0.
  return texture.sourceChannels == 2 || texture.sourceChannels == 4 ? texel.w : texel.x;
}

glm::vec2 InterpolateUv(const Mesh& mesh, const uint32_t* idx, float u, float v) {
  const glm::vec2 uv0 = mesh.uvs[idx[0]];
  return uv0 + (mesh.uvs[idx[1]] - uv0) * u + (mesh.uvs[idx[2]] - uv0) * v;
}

glm::vec3 FaceNormal(const Mesh& mesh, const uint32_t* idx) {
  const glm::vec3& p0 = mesh.positions[idx[0]];
  return glm::cross(mesh.positions[idx[1]] - p0, mesh.positions[idx[2]] - p0);
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

struct Hit {
  uint32_t triangle;
  float u, v;  // Embree's barycentrics: weights (1 - u - v, u, v) of the triangle's vertices
  float t;     // in units of the ray direction's length
};

// One Embree device and scene holding the scene's mesh as one triangle geometry, primitive i being
// triangle i of the mesh.
class RayTracer {
 public:
  explicit RayTracer(const Scene& scene) : scene_(scene) {
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
      auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
          geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
      auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
          geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), mesh.TriangleCount()));
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

// A shaded point: what the G-buffer resolve computes, unquantised and in world space.
struct Surface {
  glm::vec3 position;
  glm::vec3 normal;      // unit shading normal, on the side the ray came from
  glm::vec3 faceNormal;  // unit geometric normal, on the side the ray came from
  SurfaceMaterial material;
  float alpha;           // GGX alpha, roughness^2 clamped to kMinGgxAlpha
};

// As passes/gbuffer.cpp's resolve, with Embree's barycentrics and texture level 0 (a ray has no
// pixel footprint, and the reference wants the texels themselves).
Surface ResolveSurface(const Scene& scene, const Hit& hit, const glm::vec3& rayDirection) {
  const Mesh& mesh = scene.mesh;
  const uint32_t* idx = &mesh.indices[3 * size_t(hit.triangle)];
  const float w0 = 1.0f - hit.u - hit.v;
  Surface s;
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

// A light as the reference samples it: its prepared form plus what sampling needs.
struct SampledLight {
  PreparedLight light;
  bool castShadows;
  // Directional: 1 - cos of the cone's half-angle, and the estimator's normalisation
  // 2 / (1 + cos), the cone's solid angle over its cosine-weighted solid angle pi sin^2, so that a
  // surface facing the light receives exactly the scene's irradiance.
  float oneMinusCosMax = 0.0f;
  float coneNormalisation = 1.0f;
  Basis frame{glm::vec3(0.0f, 0.0f, 1.0f)};  // around the direction to the light
};

std::vector<SampledLight> SampleableLights(const Scene& scene) {
  const std::vector<PreparedLight> prepared = PrepareLights(scene, glm::mat4(1.0f));
  // In PrepareLights order: directional lights, spots, then point lights, which the frame does not
  // shadow (core/scene.h PointLight), so the reference does not either.
  std::vector<bool> castShadows;
  for (const DirectionalLight& l : scene.directionalLights) castShadows.push_back(l.castShadows);
  for (const SpotLight& l : scene.spotLights) castShadows.push_back(l.castShadows);
  castShadows.insert(castShadows.end(), scene.pointLights.size(), false);
  std::vector<SampledLight> lights;
  for (size_t i = 0; i < prepared.size(); ++i) {
    SampledLight s{prepared[i], castShadows[i]};
    if (!s.light.isSpot) {
      // 1 - cos(atan(t)) = t^2 / (q (q + 1)), q = sqrt(1 + t^2): no cancellation for tiny suns.
      const double t = s.light.tanAngularRadius;
      const double q = std::sqrt(1.0 + t * t);
      s.oneMinusCosMax = float(t * t / (q * (q + 1.0)));
      s.coneNormalisation = float(2.0 / (1.0 + 1.0 / q));
      s.frame = Basis(-s.light.direction);
    }
    lights.push_back(s);
  }
  return lights;
}

// One sample of a light seen from `position`: a direction, the distance to the emitter point along
// it (infinity for a directional light) and the irradiance it carries on a surface facing it,
// such that the mean over samples of BrdfCosine * irradiance estimates the reflected radiance.
struct LightSample {
  glm::vec3 toLight;
  float distance;
  glm::vec3 irradiance;
};

LightSample SampleLight(const SampledLight& s, const glm::vec3& position, float u1, float u2) {
  const PreparedLight& light = s.light;
  const float phi = 2.0f * kPi * u2;
  if (!light.isSpot) {
    // Uniform in the cone's solid angle (Pharr et al., PBR 3rd ed., §13.6.4, UniformSampleCone).
    const float oneMinusCos = u1 * s.oneMinusCosMax;
    const float cosTheta = 1.0f - oneMinusCos;
    const float sinTheta = std::sqrt(std::max(0.0f, oneMinusCos * (2.0f - oneMinusCos)));
    const glm::vec3 local(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
    return {glm::normalize(s.frame.ToWorld(local)), kInfinity, light.power * s.coneNormalisation};
  }
  // Spot: a Lambertian disc of `radius` centred on the light, facing the point, uniform in area
  // (PBR §13.6.2, concentric mapping replaced by sqrt(u1): same density). Radiance
  // L = intensity / (pi r^2) gives each sample the irradiance I cos(at the disc) / distance^2;
  // the cone falloff is the one of core/lighting.h's Evaluate, from the disc's centre.
  glm::vec3 toCentre = light.position - position;
  const float centreDistance = glm::length(toCentre);
  toCentre = centreDistance > 0.0f ? toCentre / centreDistance : -light.direction;
  const float cone =
      std::clamp((glm::dot(-toCentre, light.direction) - light.cosOuter) * light.coneScale, 0.0f, 1.0f);
  const Basis disc(-toCentre);  // the disc's normal points at the shaded point
  const float r = light.radius * std::sqrt(u1);
  const glm::vec3 onDisc = light.position + disc.t * (r * std::cos(phi)) + disc.b * (r * std::sin(phi));
  glm::vec3 toLight = onDisc - position;
  const float distance2 = glm::dot(toLight, toLight);
  const float distance = std::sqrt(distance2);
  toLight = distance > 0.0f ? toLight / distance : toCentre;
  const float cosAtDisc = std::max(0.0f, glm::dot(-toLight, disc.n));
  // The raster path's clamp: inside the emitter's radius the inverse square stops growing.
  const float falloff = cosAtDisc / std::max(distance2, std::max(light.radius * light.radius, 1e-8f));
  return {toLight, distance, light.power * (cone * cone * falloff)};
}

// The full transport's view of the same lights as emitters that a BSDF-sampled ray can meet, so
// that multiple importance sampling can weigh the two ways of finding them (Veach 1997, §9.2): the
// solid-angle density with which SampleLight draws a direction, and the light a ray along a
// direction receives. A light of zero size (a sun of angular diameter 0, a spot of radius 0) is a
// delta light: density 0 here, found by SampleLight alone.

// SampleLight's density of `sample` (drawn from `position`) in solid angle; 0 for a delta light.
// A density that overflows (a sun or disc too small for float) is a delta light's too.
float LightPdf(const SampledLight& s, const glm::vec3& position, const LightSample& sample) {
  const PreparedLight& light = s.light;
  if (!light.isSpot) {
    const float pdf = 1.0f / (2.0f * kPi * s.oneMinusCosMax);
    return s.oneMinusCosMax > 0.0f && std::isfinite(pdf) ? pdf : 0.0f;
  }
  if (!(light.radius > 0.0f)) return 0.0f;
  // Uniform in the disc's area A = pi r^2: density d^2 / (A cos) in solid angle (PBR 3rd ed., §14.2.2).
  glm::vec3 toPoint = position - light.position;
  const float centreDistance = glm::length(toPoint);
  toPoint = centreDistance > 0.0f ? toPoint / centreDistance : light.direction;
  const float cosAtDisc = glm::dot(-sample.toLight, toPoint);
  if (!(cosAtDisc > 0.0f)) return 0.0f;
  const float pdf = sample.distance * sample.distance / (kPi * light.radius * light.radius * cosAtDisc);
  return std::isfinite(pdf) ? pdf : 0.0f;
}

// Whether the ray from `position` along unit `direction` meets the light's emitter (the sun's cone
// of directions; the spot's disc, facing `position` as SampleLight places it), and if so, as
// SampleLight would have drawn that direction: `sample` (distance along the ray, irradiance) and
// its density `pdf`. The emitted radiance along the ray is then sample.irradiance * pdf: the
// radiance that makes SampleLight's estimator BrdfCosine * irradiance unbiased.
bool HitEmitter(const SampledLight& s, const glm::vec3& position, const glm::vec3& direction, LightSample& sample,
                float& pdf) {
  const PreparedLight& light = s.light;
  if (!light.isSpot) {
    if (!(s.oneMinusCosMax > 0.0f)) return false;
    // 1 - cos = |direction - axis|^2 / 2: no cancellation for a small sun.
    const glm::vec3 offAxis = direction - s.frame.n;
    if (0.5f * glm::dot(offAxis, offAxis) > s.oneMinusCosMax) return false;
    sample = {direction, kInfinity, light.power * s.coneNormalisation};
    pdf = 1.0f / (2.0f * kPi * s.oneMinusCosMax);
    return std::isfinite(pdf);
  }
  if (!(light.radius > 0.0f)) return false;
  glm::vec3 toPoint = position - light.position;
  const float centreDistance = glm::length(toPoint);
  if (!(centreDistance > 0.0f)) return false;
  toPoint /= centreDistance;  // the disc's normal
  const float cosAtDisc = -glm::dot(direction, toPoint);
  if (!(cosAtDisc > 0.0f)) return false;
  const float distance = centreDistance / cosAtDisc;  // to the disc's plane along the ray
  const glm::vec3 fromCentre = position + direction * distance - light.position;
  if (glm::dot(fromCentre, fromCentre) > light.radius * light.radius) return false;
  // As SampleLight: the cone falloff from the disc's centre, the clamped inverse square.
  const float cone = std::clamp((glm::dot(toPoint, light.direction) - light.cosOuter) * light.coneScale, 0.0f, 1.0f);
  const float falloff = cosAtDisc / std::max(distance * distance, std::max(light.radius * light.radius, 1e-8f));
  sample = {direction, distance, light.power * (cone * cone * falloff)};
  pdf = distance * distance / (kPi * light.radius * light.radius * cosAtDisc);
  return std::isfinite(pdf);
}

// The power heuristic with exponent 2 (Veach 1997, ch. 9): the weight of a sample drawn with
// density `pdf` by one strategy that another strategy draws with density `otherPdf`. Written as a
// ratio so that no density squared overflows.
float PowerHeuristic(float pdf, float otherPdf) {
  if (!(pdf > 0.0f)) return 0.0f;
  const float ratio = otherPdf / pdf;
  return 1.0f / (1.0f + ratio * ratio);
}

float Luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

struct Counters {
  size_t rays = 0;
  size_t paths = 0;
};

// How far a secondary ray starts off its surface: in proportion to the scene's extent, so float
// positions a long way from the origin do not hit their own triangle.
float RayOffset(const Scene& scene) {
  float extent = 0.0f;
  for (const glm::vec3& p : scene.mesh.positions)
    extent = std::max(extent, std::max(std::fabs(p.x), std::max(std::fabs(p.y), std::fabs(p.z))));
  return kRayOffsetScale * std::max(extent, 1.0f);
}

// The light whose visibility the reference reports (the frame's shadowed light), or none.
size_t FirstShadowLight(const std::vector<SampledLight>& lights) {
  for (size_t i = 0; i < lights.size(); ++i)
    if (lights[i].castShadows) return i;
  return std::numeric_limits<size_t>::max();
}

class Shader {
 public:
  Shader(const Scene& scene, const RayTracer& tracer, const ReferenceParams& params)
      : scene_(scene),
        tracer_(tracer),
        params_(params),
        lights_(SampleableLights(scene)),
        firstShadowLight_(FirstShadowLight(lights_)),
        rayOffset_(RayOffset(scene)) {}

  // Direct light leaving `s` towards `toViewer` (unit), each light sampled `samples` times. When
  // `visibleSamples` is given, it receives how many samples of the first shadow-casting light are
  // unoccluded (each of them is traced, whatever the BRDF there).
  glm::vec3 DirectLight(const Surface& s, const glm::vec3& toViewer, int samples, Pcg32& rng, Counters& counters,
                        int* visibleSamples) const {
    glm::vec3 radiance(0.0f);
    for (size_t i = 0; i < lights_.size(); ++i) {
      const SampledLight& light = lights_[i];
      const bool countVisibility = visibleSamples != nullptr && i == firstShadowLight_;
      glm::vec3 sum(0.0f);
      for (int k = 0; k < samples; ++k) {
        const float u1 = rng.Uniform();
        const float u2 = rng.Uniform();
        const LightSample sample = SampleLight(light, s.position, u1, u2);
        const glm::vec3 reflected =
            BrdfCosine(s.material, s.alpha, s.normal, toViewer, sample.toLight) * sample.irradiance;
        const bool contributes = reflected.x > 0.0f || reflected.y > 0.0f || reflected.z > 0.0f;
        bool visible = true;
        if (light.castShadows && (contributes || countVisibility)) {
          const glm::vec3 origin = OffsetOrigin(s, sample.toLight);
          // A spot's shadow ray ends just before the emitter point it aims at.
          const float tfar = std::isinf(sample.distance) ? kInfinity : std::max(0.0f, sample.distance - rayOffset_);
          visible = !tracer_.Occluded(origin, sample.toLight, 0.0f, tfar);
          ++counters.rays;
        }
        if (countVisibility && visible) ++*visibleSamples;
        if (visible) sum += reflected;
      }
      radiance += sum / float(samples);
    }
    return radiance;
  }

  // One GGX specular bounce of direct light at `s`: directions sampled from the distribution of
  // visible normals, weight F G2 / G1(v) (Heitz 2018, "Sampling the GGX Distribution of Visible
  // Normals", JCGT 7(4); G2 the height-correlated Smith of core/brdf.h). The
  // specular lobe only: the screen-space path reflects with the split-sum specular weight alone.
  glm::vec3 SpecularBounce(const Surface& s, const glm::vec3& toViewer, Pcg32& rng, Counters& counters) const {
    const int samples = params_.bounceSamples;
    const Basis frame(s.normal);
    const glm::vec3 v = frame.ToLocal(toViewer);
    glm::vec3 sum(0.0f);
    if (samples == 0 || !(v.z > 0.0f)) return sum;  // the BRDF is 0 for a viewer below the surface
    const glm::vec3 f0 = SpecularF0(s.material);
    const float a = s.alpha;
    const float a2 = a * a;
    const float lambdaV = std::sqrt(a2 + (1.0f - a2) * v.z * v.z);
    for (int k = 0; k < samples; ++k) {
      const float u1 = rng.Uniform();  // named: argument evaluation order is unspecified
      const float u2 = rng.Uniform();
      const glm::vec3 h = SampleVisibleNormal(v, a, u1, u2);
      const float vDotH = std::clamp(glm::dot(v, h), 0.0f, 1.0f);
      const glm::vec3 l = h * (2.0f * vDotH) - v;
      if (!(l.z > 0.0f)) continue;
      // G2 / G1(v) = n.l (n.v + lambdaV) / (n.l lambdaV + n.v lambdaL): F V 4 n.l n.v / G1(v) with
      // V = 0.5 / (n.l lambdaV + n.v lambdaL) and G1(v) = 2 n.v / (n.v + lambdaV), finite at grazing.
      const float lambdaL = std::sqrt(a2 + (1.0f - a2) * l.z * l.z);
      const float g2OverG1 = l.z * (v.z + lambdaV) / (l.z * lambdaV + v.z * lambdaL);
      const glm::vec3 weight = SchlickFresnel(vDotH, f0) * g2OverG1;
      const glm::vec3 direction = glm::normalize(frame.ToWorld(l));
      Hit hit;
      ++counters.rays;
      if (!tracer_.Intersect(RayKind::kCamera, OffsetOrigin(s, direction), direction, 0.0f, kInfinity, hit)) {
        sum += weight * params_.environment.Radiance(direction);
        continue;
      }
      const Surface next = ResolveSurface(scene_, hit, direction);
      sum += weight * DirectLight(next, -direction, params_.bounceLightSamples, rng, counters, nullptr);
    }
    return sum / float(samples);
  }

  bool HasShadowLight() const { return firstShadowLight_ < lights_.size(); }

  // Heitz 2018's sampling routine (isotropic alpha): a microfacet normal in the local frame,
  // distributed as D_v(h) = G1(v) max(0, v.h) D(h) / v.z.
  static glm::vec3 SampleVisibleNormal(const glm::vec3& v, float alpha, float u1, float u2) {
    const glm::vec3 vh = glm::normalize(glm::vec3(alpha * v.x, alpha * v.y, v.z));
    const float lengthSquared = vh.x * vh.x + vh.y * vh.y;
    const glm::vec3 t1 = lengthSquared > 0.0f ? glm::vec3(-vh.y, vh.x, 0.0f) / std::sqrt(lengthSquared)
                                              : glm::vec3(1.0f, 0.0f, 0.0f);
    const glm::vec3 t2 = glm::cross(vh, t1);
    const float r = std::sqrt(u1);
    const float phi = 2.0f * kPi * u2;
    const float p1 = r * std::cos(phi);
    const float s = 0.5f * (1.0f + vh.z);
    const float p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * (r * std::sin(phi));
    const glm::vec3 nh = t1 * p1 + t2 * p2 + vh * std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2));
    return glm::normalize(glm::vec3(alpha * nh.x, alpha * nh.y, std::max(0.0f, nh.z)));
  }

 private:
  // The start of a ray leaving `s` along `direction`: off the triangle's plane on the side the
  // ray goes, so it cannot hit its own triangle again (including rays into the surface).
  glm::vec3 OffsetOrigin(const Surface& s, const glm::vec3& direction) const {
    return s.position + s.faceNormal * (glm::dot(s.faceNormal, direction) >= 0.0f ? rayOffset_ : -rayOffset_);
  }

  const Scene& scene_;
  const RayTracer& tracer_;
  const ReferenceParams& params_;
  std::vector<SampledLight> lights_;
  size_t firstShadowLight_;
  float rayOffset_;
};

// The full transport: one path per call, from the camera through the scene (Pharr et al., PBR
// 4th ed., §13.4, PathIntegrator, with its multiple importance sampling of lights and BSDF).
struct PathRadiance {
  glm::vec3 direct{0.0f};    // the lights' light at the first hit; the environment if the camera ray misses
  glm::vec3 indirect{0.0f};  // everything else
};

// A direction drawn from the BRDF at a surface: f cos / pdf and the (mixture) density.
struct BsdfSample {
  glm::vec3 direction;
  glm::vec3 weight;
  float pdf;
};

class PathTracer {
 public:
  PathTracer(const Scene& scene, const RayTracer& tracer, const ReferenceParams& params)
      : scene_(scene),
        tracer_(tracer),
        params_(params),
        lights_(SampleableLights(scene)),
        firstShadowLight_(FirstShadowLight(lights_)),
        rayOffset_(RayOffset(scene)) {}

  bool HasShadowLight() const { return firstShadowLight_ < lights_.size(); }

  // How many of `samples` light samples of the first shadow-casting light seen from `s` reach it
  // (each traced, whatever the BRDF there): the visibility the shadow filter estimates.
  int VisibleSamples(const Surface& s, int samples, Pcg32& rng, Counters& counters) const {
    const SampledLight& light = lights_[firstShadowLight_];
    int visible = 0;
    for (int k = 0; k < samples; ++k) {
      const float u1 = rng.Uniform();
      const float u2 = rng.Uniform();
      const LightSample sample = SampleLight(light, s.position, u1, u2);
      ++counters.rays;
      visible += !Occluded(s, sample);
    }
    return visible;
  }

  // One path whose camera ray hit `hit` along `cameraDirection` (unit). The lights are not seen by
  // camera rays (the rasterized frame draws no emitter either), only by the paths' later rays.
  PathRadiance Trace(const Hit& cameraHit, const glm::vec3& cameraDirection, Pcg32& rng, Counters& counters) const {
    PathRadiance out;
    const Environment& environment = params_.environment;
    const bool environmentLights = !environment.IsBlack();
    Surface s = ResolveSurface(scene_, cameraHit, cameraDirection);
    glm::vec3 toViewer = -cameraDirection;
    glm::vec3 throughput(1.0f);
    for (int depth = 0;; ++depth) {
      glm::vec3& lightSink = depth == 0 ? out.direct : out.indirect;
      // Light sampling: one sample of every light, weighted against BSDF sampling.
      for (const SampledLight& light : lights_) {
        const float u1 = rng.Uniform();
        const float u2 = rng.Uniform();
        const LightSample sample = SampleLight(light, s.position, u1, u2);
        const glm::vec3 reflected = Reflected(s, toViewer, sample.toLight);
        if (IsZero(reflected) || IsZero(sample.irradiance)) continue;
        const float lightPdf = LightPdf(light, s.position, sample);
        const float weight = lightPdf > 0.0f ? PowerHeuristic(lightPdf, BsdfPdf(s, toViewer, sample.toLight)) : 1.0f;
        if (light.castShadows) {
          ++counters.rays;
          if (Occluded(s, sample)) continue;
        }
        lightSink += throughput * reflected * sample.irradiance * weight;
      }
      // Environment sampling, weighted against BSDF sampling.
      if (environmentLights) {
        const float u1 = rng.Uniform();
        const float u2 = rng.Uniform();
        const EnvironmentSample sample = environment.Sample(u1, u2);
        const glm::vec3 reflected = Reflected(s, toViewer, sample.direction);
        if (!IsZero(reflected) && !IsZero(sample.radiance)) {
          ++counters.rays;
          if (!tracer_.Occluded(OffsetOrigin(s, sample.direction), sample.direction, 0.0f, kInfinity)) {
            const float weight = PowerHeuristic(sample.pdf, BsdfPdf(s, toViewer, sample.direction));
            out.indirect += throughput * reflected * sample.radiance * (weight / sample.pdf);
          }
        }
      }
      // BSDF sampling: the next direction, which also finds the emitters and the environment.
      const float uLobe = rng.Uniform();
      const float u1 = rng.Uniform();
      const float u2 = rng.Uniform();
      BsdfSample bsdf;
      if (!SampleBsdf(s, toViewer, uLobe, u1, u2, bsdf)) break;
      throughput *= bsdf.weight;
      // Russian roulette (PBR 4th ed., §13.4.3): after a few bounces a path goes on with probability
      // its throughput's largest component, and survivors are weighted up by its inverse.
      if (depth >= kRussianRouletteDepth) {
        const float survival = std::min(1.0f, std::max(throughput.x, std::max(throughput.y, throughput.z)));
        if (!(rng.Uniform() < survival)) break;
        throughput /= survival;
      }
      const glm::vec3 direction = bsdf.direction;
      Hit hit{0, 0.0f, 0.0f, kInfinity};
      ++counters.rays;
      const bool found =
          tracer_.Intersect(RayKind::kBothFaces, OffsetOrigin(s, direction), direction, 0.0f, kInfinity, hit);
      for (const SampledLight& light : lights_) {
        LightSample sample;
        float lightPdf = 0.0f;
        if (!HitEmitter(light, s.position, direction, sample, lightPdf)) continue;
        // Shadowed as SampleLight's shadow ray would be: by a surface short of the emitter.
        if (light.castShadows && found && !(hit.t > std::max(0.0f, sample.distance - rayOffset_))) continue;
        lightSink += throughput * sample.irradiance * (lightPdf * PowerHeuristic(bsdf.pdf, lightPdf));
      }
      if (!found) {
        if (environmentLights) {
          const float weight = PowerHeuristic(bsdf.pdf, environment.Pdf(direction));
          out.indirect += throughput * environment.Radiance(direction) * weight;
        }
        break;
      }
      // The last vertex's ray only gathers what it sees at infinity and on the emitters.
      if (depth == params_.bounces) break;
      s = ResolveSurface(scene_, hit, direction);
      toViewer = -direction;
    }
    return out;
  }

 private:
  static constexpr int kRussianRouletteDepth = 3;

  static bool IsZero(const glm::vec3& c) { return !(c.x > 0.0f || c.y > 0.0f || c.z > 0.0f); }

  // The BRDF times n.l at `s` for unit v (to the viewer) and l (to the light): core/brdf.h's, the
  // one every path of the renderer shades with.
  static glm::vec3 Reflected(const Surface& s, const glm::vec3& v, const glm::vec3& l) {
    return BrdfCosine(s.material, s.alpha, s.normal, v, l);
  }

  // The probability of sampling the specular lobe: its share of the surface's estimated
  // directional albedo, the diffuse lobe's albedo (1 - metallic) against the specular lobe's
  // F0 A + B from the split-sum table (core/brdf.h).
  static float SpecularProbability(const Surface& s, float nDotV) {
    const float diffuse = Luminance(s.material.albedo) * (1.0f - s.material.metallic);
    const float specular = Luminance(SpecularWeight(SpecularF0(s.material), nDotV, s.material.roughness));
    return specular + diffuse > 0.0f ? specular / (specular + diffuse) : 1.0f;
  }

  // The mixture density with which SampleBsdf draws unit `l` seen from unit `v`: the lobe
  // probabilities times the cosine density n.l / pi and the GGX visible-normal density
  // D_v(h) / (4 v.h) = G1(v) D(h) / (4 n.v) = D(h) / (2 (n.v + Lv)) (Heitz 2018, eq. 17, with
  // G1(v) = 2 n.v / (n.v + Lv), Lv = sqrt(a^2 + (1 - a^2) n.v^2)).
  static float BsdfPdf(const Surface& s, const glm::vec3& v, const glm::vec3& l) {
    const float nDotV = glm::dot(s.normal, v);
    const float nDotL = glm::dot(s.normal, l);
    if (!(nDotV > 0.0f) || !(nDotL > 0.0f)) return 0.0f;
    return MixturePdf(s, nDotV, nDotL, glm::dot(s.normal, glm::normalize(v + l)), SpecularProbability(s, nDotV));
  }
  static float MixturePdf(const Surface& s, float nDotV, float nDotL, float nDotH, float specularProbability) {
    const float a2 = s.alpha * s.alpha;
    const float lambdaV = std::sqrt(a2 + (1.0f - a2) * nDotV * nDotV);
    const float specular = GgxDistribution(std::clamp(nDotH, 0.0f, 1.0f), s.alpha) / (2.0f * (nDotV + lambdaV));
    return specularProbability * specular + (1.0f - specularProbability) * (nDotL / kPi);
  }

  // Draws a direction at `s` seen from `v`: the specular lobe with SpecularProbability, by GGX
  // visible normals (Heitz 2018); else the diffuse lobe, cosine-weighted (Malley's method, PBR 4th
  // ed., §A.5.3). The weight is the whole BRDF's BrdfCosine over the mixture density (PBR 4th ed.,
  // §13.4: one-sample model of the lobes). False when the direction is below the surface.
  bool SampleBsdf(const Surface& s, const glm::vec3& v, float uLobe, float u1, float u2, BsdfSample& out) const {
    const Basis frame(s.normal);
    const glm::vec3 vLocal = frame.ToLocal(v);
    if (!(vLocal.z > 0.0f)) return false;  // the BRDF is 0 for a viewer below the surface
    const float specularProbability = SpecularProbability(s, vLocal.z);
    glm::vec3 l;
    if (uLobe < specularProbability) {
      const glm::vec3 h = Shader::SampleVisibleNormal(vLocal, s.alpha, u1, u2);
      l = h * (2.0f * glm::dot(vLocal, h)) - vLocal;
    } else {
      const float r = std::sqrt(u1);
      const float phi = 2.0f * kPi * u2;
      l = glm::vec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u1)));
    }
    if (!(l.z > 0.0f)) return false;
    out.direction = glm::normalize(frame.ToWorld(l));
    const float nDotV = glm::dot(s.normal, v);
    const float nDotL = glm::dot(s.normal, out.direction);
    if (!(nDotV > 0.0f) || !(nDotL > 0.0f)) return false;
    out.pdf = MixturePdf(s, nDotV, nDotL, glm::dot(s.normal, glm::normalize(v + out.direction)), specularProbability);
    const glm::vec3 reflected = Reflected(s, v, out.direction);
    if (!(out.pdf > 0.0f) || IsZero(reflected)) return false;
    out.weight = reflected / out.pdf;
    return std::isfinite(out.weight.x) && std::isfinite(out.weight.y) && std::isfinite(out.weight.z);
  }

  bool Occluded(const Surface& s, const LightSample& sample) const {
    // A spot's shadow ray ends just before the emitter point it aims at.
    const float tfar = std::isinf(sample.distance) ? kInfinity : std::max(0.0f, sample.distance - rayOffset_);
    return tracer_.Occluded(OffsetOrigin(s, sample.toLight), sample.toLight, 0.0f, tfar);
  }

  // As Shader::OffsetOrigin: off the triangle's plane on the side the ray goes.
  glm::vec3 OffsetOrigin(const Surface& s, const glm::vec3& direction) const {
    return s.position + s.faceNormal * (glm::dot(s.faceNormal, direction) >= 0.0f ? rayOffset_ : -rayOffset_);
  }

  const Scene& scene_;
  const RayTracer& tracer_;
  const ReferenceParams& params_;
  std::vector<SampledLight> lights_;
  size_t firstShadowLight_;
  float rayOffset_;
};

}  // namespace

size_t EstimateReferenceMemory(const Scene& scene, const ReferenceParams& params) {
  // Output planes: direct, indirect, result and its variance (RGB), the light's visibility and the
  // depth. The path tracer's per-thread state is a few hundred bytes.
  constexpr size_t kPlanes = 14;
  const size_t planes = kPlanes * hwy::ImageBase::BytesPerRow(size_t(params.width), sizeof(float)) * size_t(params.height);
  return planes + kReferenceBvhBytesPerTriangle * scene.mesh.TriangleCount() +
         scene.mesh.positions.size() * 4 * sizeof(float);
}

ReferenceOutputs RenderReference(const Scene& scene, const ReferenceParams& params,
                                 const ReferenceProgress& progress) {
  SSGI_CHECK_GE(params.lightSamples, 1);
  SSGI_CHECK_GE(params.bounceSamples, 0);
  SSGI_CHECK_GE(params.bounceLightSamples, 1);
  SSGI_CHECK_GE(params.samplesPerPixel, 1);
  SSGI_CHECK_GE(params.bounces, 0);
  const bool full = params.transport == ReferenceTransport::kFull;
  const int width = params.width, height = params.height;
  const ViewProjection view = MakePerspective(scene.camera, width, height);
  const glm::mat4 viewToWorld = glm::inverse(view.view);
  const glm::vec3 cameraPosition(viewToWorld[3]);
  const glm::mat3 viewToWorldRotation(viewToWorld);

  ReferenceOutputs out;
  Stopwatch stopwatch;
  const RayTracer tracer(scene);
  out.stats.buildMs = stopwatch.Lap();
  out.stats.bvhBytes = tracer.PeakBytes();

  const Shader shader(scene, tracer, params);
  const PathTracer pathTracer(scene, tracer, params);
  out.direct = MakePlane3<float>(width, height, 0.0f);
  out.indirect = MakePlane3<float>(width, height, 0.0f);
  out.result = MakePlane3<float>(width, height, 0.0f);
  out.resultVariance = MakePlane3<float>(width, height, 0.0f);
  out.lightVisibility = MakePlane<float>(width, height, 1.0f);
  out.depth = MakePlane<float>(width, height, kBackgroundDepth);

  const size_t bands = RowBandCount(size_t(height));
  std::vector<Counters> counters(bands);
  std::vector<size_t> covered(bands, 0);
  std::mutex progressMutex;
  size_t rowsDone = 0;
  ParallelForRowBands("reference", size_t(height), [&](size_t band, size_t yBegin, size_t yEnd) {
    for (size_t y = yBegin; y < yEnd; ++y) {
      float* direct[3] = {out.direct.c[0].MutableRow(y), out.direct.c[1].MutableRow(y), out.direct.c[2].MutableRow(y)};
      float* indirect[3] = {out.indirect.c[0].MutableRow(y), out.indirect.c[1].MutableRow(y),
                            out.indirect.c[2].MutableRow(y)};
      float* result[3] = {out.result.c[0].MutableRow(y), out.result.c[1].MutableRow(y), out.result.c[2].MutableRow(y)};
      float* variance[3] = {out.resultVariance.c[0].MutableRow(y), out.resultVariance.c[1].MutableRow(y),
                            out.resultVariance.c[2].MutableRow(y)};
      float* visibility = out.lightVisibility.MutableRow(y);
      float* depth = out.depth.MutableRow(y);
      for (int x = 0; x < width; ++x) {
        // One stream per pixel, its samples drawn in a fixed order: the bytes depend on neither
        // the thread count nor the order pixels run in.
        const uint64_t pixel = uint64_t(y) * uint64_t(width) + uint64_t(x);
        Pcg32 rng(Mix64((uint64_t(params.seed) << 32) ^ pixel), pixel);
        if (full) {
          // The pixel-centre ray gives the depth and the light's visibility, from a stream of their
          // own so that the paths' samples do not depend on them.
          const glm::vec3 centreDirection =
              viewToWorldRotation * view.PixelRay(float(x) + 0.5f, float(y) + 0.5f).direction;
          Hit centreHit;
          ++counters[band].rays;
          const bool centreFound =
              tracer.Intersect(RayKind::kCamera, cameraPosition, centreDirection, view.nearPlane, kInfinity, centreHit);
          if (centreFound) {
            ++covered[band];
            depth[x] = centreHit.t;
            if (pathTracer.HasShadowLight()) {
              Pcg32 visibilityRng(Mix64((uint64_t(params.seed) << 32) ^ pixel), pixel | (uint64_t(1) << 62));
              const Surface s = ResolveSurface(scene, centreHit, glm::normalize(centreDirection));
              visibility[x] =
                  float(pathTracer.VisibleSamples(s, params.samplesPerPixel, visibilityRng, counters[band])) /
                  float(params.samplesPerPixel);
            }
          }
          // Sums in double, in sample order: the sample variance needs the sum of squares without
          // cancellation.
          double sumDirect[3] = {0.0, 0.0, 0.0}, sumIndirect[3] = {0.0, 0.0, 0.0}, sumSquares[3] = {0.0, 0.0, 0.0};
          for (int k = 0; k < params.samplesPerPixel; ++k) {
            glm::vec3 direction = centreDirection;
            Hit hit = centreHit;
            bool found = centreFound;
            if (!params.pixelCentre) {
              // A box filter: the ray through a uniform point of the pixel.
              const float jx = rng.Uniform();
              const float jy = rng.Uniform();
              direction = viewToWorldRotation * view.PixelRay(float(x) + jx, float(y) + jy).direction;
              ++counters[band].rays;
              found = tracer.Intersect(RayKind::kCamera, cameraPosition, direction, view.nearPlane, kInfinity, hit);
            }
            ++counters[band].paths;
            const glm::vec3 unitDirection = glm::normalize(direction);
            PathRadiance path;
            if (found) {
              path = pathTracer.Trace(hit, unitDirection, rng, counters[band]);
            } else {
              path.direct = params.environment.Radiance(unitDirection);
            }
            for (int c = 0; c < 3; ++c) {
              sumDirect[c] += double(path.direct[c]);
              sumIndirect[c] += double(path.indirect[c]);
              const double sample = double(path.direct[c]) + double(path.indirect[c]);
              sumSquares[c] += sample * sample;
            }
          }
          const double n = double(params.samplesPerPixel);
          for (int c = 0; c < 3; ++c) {
            const double sum = sumDirect[c] + sumIndirect[c];
            direct[c][x] = float(sumDirect[c] / n);
            indirect[c][x] = float(sumIndirect[c] / n);
            result[c][x] = direct[c][x] + indirect[c][x];
            // The sample variance over n, the variance of the mean; unknown (0) from one sample.
            variance[c][x] = n > 1.0 ? float(std::max(0.0, sumSquares[c] - sum * sum / n) / ((n - 1.0) * n)) : 0.0f;
          }
          continue;
        }
        // The view ray has z = -1 in view space, so its t is the view depth and the camera's near
        // plane is tnear: the same clipping as the rasterizer's.
        const glm::vec3 rayDirection =
            viewToWorldRotation * view.PixelRay(float(x) + 0.5f, float(y) + 0.5f).direction;
        Hit hit;
        ++counters[band].rays;
        glm::vec3 directLight = params.environment.Radiance(glm::normalize(rayDirection)), indirectLight(0.0f);
        if (tracer.Intersect(RayKind::kCamera, cameraPosition, rayDirection, view.nearPlane, kInfinity, hit)) {
          ++covered[band];
          const glm::vec3 unitDirection = glm::normalize(rayDirection);
          const Surface s = ResolveSurface(scene, hit, unitDirection);
          int visible = 0;
          directLight = shader.DirectLight(s, -unitDirection, params.lightSamples, rng, counters[band], &visible);
          indirectLight = shader.SpecularBounce(s, -unitDirection, rng, counters[band]);
          if (shader.HasShadowLight()) visibility[x] = float(visible) / float(params.lightSamples);
          depth[x] = hit.t;
        }
        for (int c = 0; c < 3; ++c) {
          direct[c][x] = directLight[c];
          indirect[c][x] = indirectLight[c];
          result[c][x] = directLight[c] + indirectLight[c];
        }
      }
    }
    if (progress) {
      const std::lock_guard<std::mutex> lock(progressMutex);
      rowsDone += yEnd - yBegin;
      progress(rowsDone, size_t(height));
    }
  });
  for (size_t b = 0; b < bands; ++b) {
    out.stats.rays += counters[b].rays;
    out.stats.paths += counters[b].paths;
    out.stats.coveredPixels += covered[b];
  }
  out.stats.traceMs = stopwatch.Lap();
  return out;
}

}  // namespace ssgi
