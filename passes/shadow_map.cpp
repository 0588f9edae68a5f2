#include "passes/shadow_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "core/check.h"
#include "core/lighting.h"
#include "core/parallel.h"
#include "core/raster/scene_raster_input.h"
#include "core/stopwatch.h"

namespace ssgi {
namespace {

constexpr size_t kVerticesPerItem = 16384;  // mesh vertices per parallel work item

constexpr float kMaxSpotFovDegrees = 170.0f;
constexpr float kMinSpotNear = 1e-3f;     // metres
constexpr float kMinHalfExtent = 1e-3f;   // metres; a single receiver still gets a map of some size
constexpr float kMinDepthMargin = 1e-3f;  // metres between the outermost geometry and near / far

// The golden angle pi (3 - sqrt 5) of Vogel's sunflower spiral (Vogel 1979), as cos and sin, so the
// pattern needs no libm call and is the same on every target.
constexpr double kCosGoldenAngle = -0.7373688780783197;
constexpr double kSinGoldenAngle = 0.6754902942615238;

// (x, y, depth) of a point in a light view: depth = -z_view, the distance along the view axis.
glm::vec3 LightCoordinates(const glm::mat4& view, const glm::vec3& world) {
  const glm::vec3 v(view * glm::vec4(world, 1.0f));
  return {v.x, v.y, -v.z};
}

// Light-view bounds of every mesh vertex: the casters. Per-item partials combined in item order.
LightViewBounds CasterBounds(const Mesh& mesh, const glm::mat4& view) {
  const size_t items = (mesh.positions.size() + kVerticesPerItem - 1) / kVerticesPerItem;
  std::vector<LightViewBounds> partial(items);
  ParallelFor("shadow_map.caster_bounds", items, [&](size_t item) {
    const size_t end = std::min(mesh.positions.size(), (item + 1) * kVerticesPerItem);
    for (size_t i = item * kVerticesPerItem; i < end; ++i) partial[item].Add(LightCoordinates(view, mesh.positions[i]));
  });
  LightViewBounds all;
  for (const LightViewBounds& b : partial) all.Add(b);
  return all;
}

// The G-buffer pixels with geometry: how many, and the light-view bounds of their positions (the
// receivers). Per-band partials combined in band order.
struct Receivers {
  size_t count = 0;
  LightViewBounds bounds;
};
Receivers ScanReceivers(const GBuffer& gbuffer, const ReceiverPositions& positions, KernelPath kernels) {
  const size_t height = size_t(gbuffer.height());
  const int width = gbuffer.width();
  const auto boundsRow = kernels == KernelPath::kSimd ? ReceiverBoundsRowSimd : ReceiverBoundsRowScalar;
  std::vector<Receivers> partial(RowBandCount(height));
  ParallelForRowBands("shadow_map.receivers", height, [&](size_t band, size_t yBegin, size_t yEnd) {
    Receivers& r = partial[band];
    for (int y = int(yBegin); y < int(yEnd); ++y)
      r.count += boundsRow(gbuffer.word[GBufferWord::kDepth].ConstRow(y), width, positions, positions.AtRow(y),
                           r.bounds.lo, r.bounds.hi);
  });
  Receivers all;
  for (const Receivers& r : partial) {
    all.count += r.count;
    all.bounds.Add(r.bounds);
  }
  return all;
}

// Directional light: an orthographic view along the light, its (x, y) window the receivers' bounds
// (in ShadowFitRotation's view) padded by the widest search radius plus the normal offset, its
// near plane behind every caster of the scene (casters outside the camera's view still cast), its
// far plane behind every receiver.
ViewProjection FitDirectional(const PreparedLight& light, const Scene& scene, const LightViewBounds& receivers,
                              const ShadowMapParams& params) {
  const glm::vec3 up = UpHint(light.direction);
  const glm::mat4 rotation = ShadowFitRotation(light);
  const LightViewBounds casters = CasterBounds(scene.mesh, rotation);
  const float nearDepth = std::min(receivers.lo.z, casters.lo.z);
  const float margin = std::max(kMinDepthMargin, 1e-3f * (receivers.hi.z - nearDepth));
  const float eyeDepth = nearDepth - margin;
  const float farPlane = receivers.hi.z + margin - eyeDepth;
  const float pad = std::min(farPlane, params.maxBlockerDistance) * light.tanAngularRadius;
  // The normal offset and the texel rounding of the taps reach kNormalOffsetTexels + 1 texels further.
  const float texelMargin = 1.0f + 2.0f * (kNormalOffsetTexels + 1.0f) / float(params.resolution);
  const float halfX = std::max(kMinHalfExtent, (0.5f * (receivers.hi.x - receivers.lo.x) + pad) * texelMargin);
  const float halfY = std::max(kMinHalfExtent, (0.5f * (receivers.hi.y - receivers.lo.y) + pad) * texelMargin);
  const glm::vec3 centre(0.5f * (receivers.lo.x + receivers.hi.x), 0.5f * (receivers.lo.y + receivers.hi.y), -eyeDepth);
  const glm::vec3 eye = glm::transpose(glm::mat3(rotation)) * centre;
  return MakeOrthographic(eye, light.direction, up, halfX, halfY, 0.0f, farPlane, params.resolution,
                          params.resolution);
}

// Spot light: a perspective view from the emitter along the cone axis covering the outer cone, its
// near plane just before the nearest vertex of the scene.
ViewProjection FitSpot(const PreparedLight& light, const SpotLight& spot, const Scene& scene,
                       const ShadowMapParams& params) {
  CameraDesc desc;
  desc.position = light.position;
  desc.target = light.position + light.direction;
  desc.up = UpHint(light.direction);
  desc.fovYDegrees = std::min(2.0f * spot.outerConeDegrees, kMaxSpotFovDegrees);
  const LightViewBounds casters = CasterBounds(scene.mesh, glm::lookAt(desc.position, desc.target, desc.up));
  desc.nearPlane = casters.Empty() ? kMinSpotNear : std::max(kMinSpotNear, 0.99f * casters.lo.z);
  return MakePerspective(desc, params.resolution, params.resolution);
}

// The PCSS blocker search (Fernando 2005, §3.1) for the receiver at light-view position `p`: the
// shadow term of word 3.
template <bool kOrthographic>
uint32_t SearchBlockers(const BlockerSearchContext& s, const glm::vec3& p, uint32_t word1) {
  const ViewProjection& light = s.light;
  const float resolution = float(light.width);
  const glm::vec3 n = s.normalToLight * UnpackNormal(word1, s.encoding);
  const float depth = -p.z;
  if (!(depth > light.nearPlane)) return kShadowLit;
  // Distance from the light along its ray: orthographic, from the view's origin plane.
  const float distance = kOrthographic ? depth : glm::length(p);
  const glm::vec3 toLight = kOrthographic ? glm::vec3(0.0f, 0.0f, 1.0f) : -p / distance;
  const float cosAngle = glm::dot(n, toLight);
  const float sinAngle = std::sqrt(std::max(0.0f, 1.0f - cosAngle * cosAngle));
  const float slope = cosAngle * kMaxSlope > sinAngle ? sinAngle / cosAngle : kMaxSlope;
  const float texel = std::max(s.texelX, s.texelY) * (kOrthographic ? 1.0f : depth);
  const glm::vec3 biased = p + n * (kNormalOffsetTexels * texel * sinAngle);
  const float biasedDepth = -biased.z;
  if (!(biasedDepth > light.nearPlane)) return kShadowLit;
  const float toUnitDepth = kOrthographic ? 1.0f : 1.0f / biasedDepth;
  const glm::vec2 centre((biased.x * toUnitDepth + light.halfX) * s.invTexelX,
                         (light.halfY - biased.y * toUnitDepth) * s.invTexelY);
  if (!(centre.x >= 0.0f && centre.x < resolution && centre.y >= 0.0f && centre.y < resolution)) return kShadowLit;
  const float bias = texel * (kConstantBiasTexels + kSlopeBiasTexels * slope);

  // Search radius in texels: the penumbra a blocker between the receiver and the light could cast.
  // Directional: the light's angular radius times the blocker's distance, at most the distance to the
  // near plane. Spot: similar triangles from the emitter's disc to the receiver, projected on the
  // nearest plane a blocker can lie on (NVIDIA's PCSS sample, Bavoil 2008).
  glm::vec2 radius;
  if (kOrthographic) {
    const float world = std::min(depth - light.nearPlane, s.maxBlockerDistance) * s.tanAngularRadius;
    radius = {world * s.invTexelX, world * s.invTexelY};
  } else {
    const float nearest = std::max(light.nearPlane, depth - s.maxBlockerDistance);
    radius = glm::vec2(s.lightRadius * (depth - nearest) / (depth * nearest) * s.invTexelX);
  }
  radius = glm::min(radius, glm::vec2(resolution));

  // The receiver's tangent plane along the ray through texel centre (tx + 0.5, ty + 0.5): a blocker
  // must lie in front of it. That ray's xy (orthographic: its origin; perspective: at unit depth) is
  // r = ((tx + 0.5) texelX - halfX, halfY - (ty + 0.5) texelY); with m = n.xy . r, affine in (tx, ty),
  // the plane's depth along it is biasedDepth + (k m - n.xy . biased.xy) / facing, where k = 1 and
  // facing = n.z (orthographic) or k = biasedDepth and facing = n.z - m (perspective): -n . direction.
  const float m0 = n.x * (0.5f * s.texelX - light.halfX) + n.y * (light.halfY - 0.5f * s.texelY);
  const float mx = n.x * s.texelX, my = -n.y * s.texelY;
  const float c = n.x * biased.x + n.y * biased.y;
  // Clamping the facing bounds the plane's depth slope by kMaxSlope.
  const float minFacing = std::max(std::sqrt(n.x * n.x + n.y * n.y) / kMaxSlope, kMinFacing);
  const float invFacing = kOrthographic ? 1.0f / std::max(n.z, minFacing) : 0.0f;

  bool hardShadow = false;
  int blockers = 0;
  float blockerDistanceSum = 0.0f;
  const glm::vec2* pattern = s.pattern;
  for (size_t i = 0; i < s.taps; ++i) {
    const glm::vec2 tap = centre + pattern[i] * radius;
    if (!(tap.x >= 0.0f && tap.x < resolution && tap.y >= 0.0f && tap.y < resolution)) continue;
    const int tx = int(tap.x), ty = int(tap.y);
    const float key = s.depthKey.ConstRow(size_t(ty))[tx];
    if (key == 0.0f) continue;  // nothing drawn: no blocker
    const float m = m0 + mx * float(tx) + my * float(ty);
    const float planeDepth = kOrthographic ? biasedDepth + (m - c) * invFacing
                                           : biasedDepth + (biasedDepth * m - c) / std::max(n.z - m, minFacing);
    const float tapDepth = light.DepthFromKey(key);
    if (!(tapDepth < planeDepth - bias)) continue;
    hardShadow = hardShadow || i == 0;
    ++blockers;
    if constexpr (kOrthographic) {
      blockerDistanceSum += tapDepth;
    } else {
      const glm::vec3 ray((float(tx) + 0.5f) * s.texelX - light.halfX, light.halfY - (float(ty) + 0.5f) * s.texelY,
                          1.0f);
      blockerDistanceSum += tapDepth * glm::length(ray);
    }
  }
  if (blockers == 0) return kShadowLit;
  // Distances along the light's rays: the receiver's (unbiased) and the blockers' mean.
  const float average = std::max(0.0f, distance - blockerDistanceSum / float(blockers));
  return PackShadowTerm(hardShadow, average);
}

template <bool kOrthographic>
void SearchBlockersRow(const BlockerSearchContext& context, const uint32_t* word1, const uint32_t* word2, int y,
                       int width, uint32_t* shadowTerm) {
  const ReceiverPositions::Row row = context.receivers.AtRow(y);
  for (int x = 0; x < width; ++x) {
    const float depth = UnpackDepth(word2[x]);
    shadowTerm[x] = depth < kBackgroundDepth
                        ? SearchBlockers<kOrthographic>(context, context.receivers.At(row, x, depth), word1[x])
                        : kShadowLit;
  }
}

}  // namespace

size_t ReceiverBoundsRowScalar(const uint32_t* word2, int width, const ReceiverPositions& positions,
                               const ReceiverPositions::Row& row, glm::vec3& lo, glm::vec3& hi) {
  size_t count = 0;
  for (int x = 0; x < width; ++x) {
    const float depth = UnpackDepth(word2[x]);
    if (!(depth < kBackgroundDepth)) continue;
    ++count;
    const glm::vec3 p = positions.At(row, x, depth);
    const glm::vec3 q(p.x + 0.0f, p.y + 0.0f, -p.z + 0.0f);
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  return count;
}

void BlockerSearchRowScalar(const BlockerSearchContext& context, const uint32_t* word1, const uint32_t* word2, int y,
                            int width, uint32_t* shadowTerm) {
  if (context.light.orthographic) {
    SearchBlockersRow<true>(context, word1, word2, y, width, shadowTerm);
  } else {
    SearchBlockersRow<false>(context, word1, word2, y, width, shadowTerm);
  }
}

// Tap i of n in the unit disc: radius sqrt(i / (n - 1)), angle i * golden angle. Tap 0 is the centre
// (the receiver's own texel, which gives the hard-shadow flag) and tap n - 1 is on the rim; equal
// areas per tap, no two taps on one ray from the centre.
std::vector<glm::vec2> BlockerSearchPattern(int taps) {
  std::vector<glm::vec2> pattern(size_t(taps), glm::vec2(0.0f));
  double c = 1.0, s = 0.0;  // cos and sin of i * golden angle, by repeated rotation
  for (int i = 0; i < taps; ++i) {
    const double r = taps > 1 ? std::sqrt(double(i) / double(taps - 1)) : 0.0;
    pattern[size_t(i)] = glm::vec2(float(r * c), float(r * s));
    const double nextC = c * kCosGoldenAngle - s * kSinGoldenAngle;
    s = s * kCosGoldenAngle + c * kSinGoldenAngle;
    c = nextC;
  }
  return pattern;
}

BlockerSearchContext MakeBlockerSearchContext(const ReceiverPositions& receivers, const ShadowMapOutputs& map,
                                              const PreparedLight& light, const std::vector<glm::vec2>& pattern,
                                              float maxBlockerDistance, NormalEncoding encoding) {
  const ViewProjection& lightView = map.lightView;
  const float resolution = float(lightView.width);
  return {
      receivers,
      lightView,
      map.shadowMap.depthKey,
      pattern.data(),
      pattern.size(),
      receivers.Rotation(),
      2.0f * lightView.halfX / resolution,
      2.0f * lightView.halfY / resolution,
      resolution / (2.0f * lightView.halfX),
      resolution / (2.0f * lightView.halfY),
      light.tanAngularRadius,
      light.radius,
      maxBlockerDistance,
      encoding,
  };
}

void RunBlockerSearch(const BlockerSearchContext& context, const GBuffer& gbuffer, Plane<uint32_t>& shadowTerm,
                      KernelPath kernels) {
  const int width = gbuffer.width();
  const auto searchRow = kernels == KernelPath::kSimd ? BlockerSearchRowSimd : BlockerSearchRowScalar;
  ParallelForRowBands("shadow_map.blocker_search", size_t(gbuffer.height()), [&](size_t, size_t yBegin, size_t yEnd) {
    for (int y = int(yBegin); y < int(yEnd); ++y)
      searchRow(context, gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(y),
                gbuffer.word[GBufferWord::kDepth].ConstRow(y), y, width, shadowTerm.MutableRow(y));
  });
}

std::vector<size_t> ShadowCastingLights(const Scene& scene) {
  std::vector<size_t> lights;
  for (size_t i = 0; i < scene.directionalLights.size(); ++i)
    if (scene.directionalLights[i].castShadows) lights.push_back(i);
  for (size_t i = 0; i < scene.spotLights.size(); ++i)
    if (scene.spotLights[i].castShadows) lights.push_back(scene.directionalLights.size() + i);
  return lights;
}

glm::mat4 ShadowFitRotation(const PreparedLight& light) {
  if (light.isSpot) return glm::mat4(1.0f);
  return glm::lookAt(glm::vec3(0.0f), light.direction, UpHint(light.direction));
}

ViewProjection FitLightView(const Scene& scene, size_t lightIndex, size_t receiverCount,
                            const LightViewBounds& receivers, const ShadowMapParams& params) {
  const PreparedLight light = PrepareLights(scene, glm::mat4(1.0f))[lightIndex];  // world space
  const size_t directionalCount = scene.directionalLights.size();
  if (light.isSpot) return FitSpot(light, scene.spotLights[lightIndex - directionalCount], scene, params);
  if (receiverCount > 0) return FitDirectional(light, scene, receivers, params);
  // Nothing receives a shadow: a unit window at the origin, only so the output is a valid view.
  return MakeOrthographic(glm::vec3(0.0f), light.direction, UpHint(light.direction), 1.0f, 1.0f, 0.0f, 1.0f,
                          params.resolution, params.resolution);
}

ViewProjection FitShadowMapView(const Scene& scene, const ViewProjection& camera, const GBuffer& gbuffer,
                                size_t lightIndex, const ShadowMapParams& params, KernelPath kernels,
                                size_t& receiverCount) {
  const PreparedLight light = PrepareLights(scene, glm::mat4(1.0f))[lightIndex];  // world space
  // One sweep counts the receivers and bounds them in the directional light's view (a spot's view is
  // fitted to its cone instead, and its bounds go unused).
  const Receivers receivers =
      ScanReceivers(gbuffer, ReceiverPositions(camera, ShadowFitRotation(light) * glm::inverse(camera.view)), kernels);
  receiverCount = receivers.count;
  return FitLightView(scene, lightIndex, receivers.count, receivers.bounds, params);
}

ShadowMapStats RunShadowMap(const ShadowMapInputs& in, const ShadowMapParams& params, ShadowMapOutputs& out,
                            Plane<uint32_t>& shadowTerm, KernelPath kernels) {
  const Scene& scene = in.scene;
  const GBuffer& gbuffer = in.gbuffer;
  const int width = gbuffer.width(), height = gbuffer.height();
  SSGI_CHECK(!in.camera.orthographic);
  SSGI_CHECK_EQ(in.camera.width, width);
  SSGI_CHECK_EQ(in.camera.height, height);
  SSGI_CHECK_EQ(int(shadowTerm.xsize()), width);
  SSGI_CHECK_EQ(int(shadowTerm.ysize()), height);
  SSGI_CHECK_GE(params.resolution, 1);
  SSGI_CHECK_LE(params.resolution, kMaxImageSize);
  SSGI_CHECK_GE(params.blockerSearchTaps, 1);
  SSGI_CHECK_LE(params.blockerSearchTaps, kMaxBlockerSearchTaps);
  SSGI_CHECK_GT(params.maxBlockerDistance, 0.0f);
  const std::vector<PreparedLight> lights = PrepareLights(scene, glm::mat4(1.0f));  // world space
  SSGI_CHECK_LT(in.light, lights.size());
  const PreparedLight& light = lights[in.light];
  const size_t directionalCount = scene.directionalLights.size();
  SSGI_CHECK(light.isSpot ? scene.spotLights[in.light - directionalCount].castShadows
                          : scene.directionalLights[in.light].castShadows);
  ShadowMapStats stats;
  Stopwatch stopwatch;

  out.lightView = FitShadowMapView(scene, in.camera, gbuffer, in.light, params, kernels, stats.pixels);
  stats.fitMs = stopwatch.Lap();

  // The rasterizer overwrites every texel, so a map of the right size from an earlier frame is
  // reused as it is: a new 16 MiB map (2048^2) costs a fill and, on fresh pages, 4096 page faults.
  const size_t resolution = size_t(params.resolution);
  const bool reused = out.shadowMap.depthKey.xsize() == resolution && out.shadowMap.depthKey.ysize() == resolution;
  if (!reused) out.shadowMap = MakeVisibilityBuffer(params.resolution, params.resolution, RasterOutput::kDepthOnly);
  if (stats.pixels == 0) {
    if (reused)
      for (size_t y = 0; y < resolution; ++y) std::fill_n(out.shadowMap.depthKey.MutableRow(y), resolution, 0.0f);
    for (int y = 0; y < height; ++y) std::fill_n(shadowTerm.MutableRow(y), width, kShadowLit);
    return stats;
  }

  // Both faces are drawn: thin and open geometry (a leaf, a ground plane seen from below, a mesh with
  // holes) must cast from either side, and the normal offset plus the receiver-plane test, not
  // front-face culling, keep lit surfaces free of acne. Cut-outs (map_d) cast through their holes.
  // A closed surface's back faces are the exception: behind its front faces from a light outside
  // it, they are culled, which halves a solid object's work and leaves the nearest depths as they were.
  if (out.closedSurfaces.meshHash != MeshGeometryHash(scene.mesh) ||
      out.closedSurfaces.surface.size() != scene.mesh.TriangleCount())
    out.closedSurfaces = FindClosedSurfaces(scene.mesh);
  const SceneRasterInput raster(scene, out.lightView, false, &out.closedSurfaces);
  stats.raster = Rasterize(raster.Get(), out.lightView, RasterOutput::kDepthOnly, out.shadowMap, nullptr, kernels);
  stats.triangles = raster.Get().triangleCount;
  stats.rasterMs = stopwatch.Lap();

  const ReceiverPositions positions(in.camera, out.lightView.view * glm::inverse(in.camera.view));
  const std::vector<glm::vec2> pattern = BlockerSearchPattern(params.blockerSearchTaps);
  const BlockerSearchContext context =
      MakeBlockerSearchContext(positions, out, light, pattern, params.maxBlockerDistance, gbuffer.normalEncoding);
  RunBlockerSearch(context, gbuffer, shadowTerm, kernels);
  stats.searchMs = stopwatch.Lap();
  return stats;
}

}  // namespace ssgi
