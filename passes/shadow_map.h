// Shadow map and PCSS blocker search (docs/design.md §3 word 3, §4, §5; docs/pipeline.md §Shadow map and
// blocker search). For one shadow-casting light:
//  1. rasterizes the scene's depth from the light with the G-buffer's rasterizer (depth only, both
//     faces, but the back faces of closed surfaces wholly beyond the near plane): orthographic for a directional light,
//     fitted to the receivers the camera sees and pulled back to every caster of the scene; perspective along the cone
//     axis for a spot light;
//  2. runs the blocker search of Percentage-Closer Soft Shadows (Fernando 2005) for every G-buffer
//     pixel, with a normal-offset receiver and a receiver-plane depth test, and writes the result as
//     the G-buffer's shadow term (word 3, PackShadowTerm).
// Cut-out (map_d) casters are alpha tested.
// The frame runs it once per shadow-casting light; G-buffer word 3 holds the term of the FIRST
// shadow-casting light (ShadowCastingLights(scene).front()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/camera.h"
#include "core/closed_surfaces.h"
#include "core/gbuffer.h"
#include "core/kernel_path.h"
#include "core/lighting.h"
#include "core/plane.h"
#include "core/raster/raster.h"
#include "core/scene.h"

namespace ssgi {

inline constexpr int kMaxBlockerSearchTaps = 256;

struct ShadowMapParams {
  int resolution = 2048;  // shadow map width and height in texels, [1, kMaxImageSize]
  // Blocker-search taps per pixel, [1, kMaxBlockerSearchTaps], including the centre tap (tap 0). 8,
  // not the paper's 16: the sweep measured 8 at least as accurate on every metric of both scenes
  // (docs/user-guide.md "Accuracy and time"), at half the search's gathers.
  int blockerSearchTaps = 8;
  // Metres, > 0. The search region is the penumbra of a blocker at most this far from the receiver
  // along the light; it bounds the region (and the directional map's padding) in large scenes.
  float maxBlockerDistance = 5.0f;
};

struct ShadowMapInputs {
  const Scene& scene;           // mesh, materials, lights
  const ViewProjection& camera; // the perspective camera the G-buffer was rendered with
  const GBuffer& gbuffer;       // reads word 1 (normal) and word 2 (view depth) only
  size_t light;                 // index in PrepareLights order (directional lights, then spots);
                                // the light must cast shadows
};

struct ShadowMapOutputs {
  // Reversed-Z depth keys seen from the light, resolution x resolution, 0 where nothing was drawn
  // (read with lightView.DepthFromKey). Kept for dumps and the SSABSS pass.
  VisibilityBuffer shadowMap;
  // The light's camera: world -> light view -> clip; orthographic (directional) or perspective (spot).
  ViewProjection lightView;
  // The mesh's closed surfaces, whose back faces the map culls (CulledClosedSurfaces): found in the
  // first frame and kept while the mesh's geometry holds (MeshGeometryHash).
  ClosedSurfaces closedSurfaces;
};

struct ShadowMapStats {
  RasterStats raster;
  double fitMs = 0.0;     // receiver and caster bounds, light camera
  double rasterMs = 0.0;  // shadow-map rasterization
  double searchMs = 0.0;  // blocker search over the G-buffer
  size_t triangles = 0;   // triangles submitted to the shadow map
  size_t pixels = 0;      // receivers searched (G-buffer pixels with geometry)
};

// shadowTerm: the shadow term of every G-buffer pixel (PackShadowTerm), written for every pixel,
// kShadowLit for background and for receivers outside the shadow map. Same size as the G-buffer;
// normally the G-buffer's own word[GBufferWord::kShadowTerm] (the pass never reads word 3). `out` may hold the map of
// an earlier frame: one of the same resolution is overwritten in place. `kernels` picks the raster's tile kernel and
// the blocker search's row kernel; both paths give the same bytes.
ShadowMapStats RunShadowMap(const ShadowMapInputs& in, const ShadowMapParams& params, ShadowMapOutputs& out,
                            Plane<uint32_t>& shadowTerm, KernelPath kernels = KernelPath::kSimd);

// Light-view bounds of points as (x, y, depth = -z_view), combined by glm::min and glm::max (so in
// any order).
struct LightViewBounds {
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};
  void Add(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void Add(const LightViewBounds& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  bool Empty() const { return !(lo.x <= hi.x); }
};

// The view the receivers are bounded in before a light's window is fitted: a directional light's
// rotation (world -> light view, through the origin); the identity for a spot, fitted to its cone.
glm::mat4 ShadowFitRotation(const PreparedLight& light);

// §Light camera from the receivers: light `lightIndex` (PrepareLights order)'s view, given how many
// receivers there are and their bounds in ShadowFitRotation's view. FitShadowMapView finds them on
// the CPU; a port that finds them on its GPU calls this for the same view.
ViewProjection FitLightView(const Scene& scene, size_t lightIndex, size_t receiverCount,
                            const LightViewBounds& receivers, const ShadowMapParams& params);

// §Light camera alone: the view RunShadowMap rasterizes light `light` (PrepareLights order) from,
// fitted to the receivers of the G-buffer's word 2 (seen through `camera`), whose count goes to
// `receivers`; `kernels` picks the receivers' row kernel (both give the same view).
ViewProjection FitShadowMapView(const Scene& scene, const ViewProjection& camera, const GBuffer& gbuffer, size_t light,
                                const ShadowMapParams& params, KernelPath kernels, size_t& receivers);

// Indices (PrepareLights order) of the lights that cast shadows, in that order. The first one is the
// light whose shadow term the G-buffer's word 3 holds.
std::vector<size_t> ShadowCastingLights(const Scene& scene);

// Light-view positions of G-buffer pixels. The camera ray's direction is affine in x along a row, so
// a row costs two PixelRay calls and a pixel three multiply-adds and a scale by its view depth.
class ReceiverPositions {
 public:
  ReceiverPositions(const ViewProjection& camera, const glm::mat4& cameraToLight)
      : camera_(camera), origin_(cameraToLight[3]), rotation_(cameraToLight) {}

  struct Row {
    glm::vec3 first, step;  // light-view ray directions: pixel 0 and the change per pixel
  };
  Row AtRow(int y) const {
    const float py = float(y) + 0.5f;
    const glm::vec3 first = rotation_ * camera_.PixelRay(0.5f, py).direction;
    const glm::vec3 last = rotation_ * camera_.PixelRay(float(camera_.width) - 0.5f, py).direction;
    return {first, camera_.width > 1 ? (last - first) / float(camera_.width - 1) : glm::vec3(0.0f)};
  }
  glm::vec3 At(const Row& row, int x, float viewDepth) const {
    return origin_ + (row.first + row.step * float(x)) * viewDepth;
  }
  const glm::vec3& Origin() const { return origin_; }
  const glm::mat3& Rotation() const { return rotation_; }

 private:
  const ViewProjection& camera_;
  glm::vec3 origin_;    // the camera's position in the light view
  glm::mat3 rotation_;  // camera view -> light view
};

// Bias (docs/pipeline.md §Shadow map and blocker search). The receiver moves along its normal by
// kNormalOffsetTexels texels times sin(angle between normal and light) (normal offset, Holbert 2011,
// "Saying goodbye to shadow acne"); every tap compares against the receiver's tangent plane along the
// tap's own ray (receiver plane depth bias, Isidoro 2006, "Shadow mapping: GPU-based tips and
// techniques"), minus kConstantBiasTexels + kSlopeBiasTexels * tan(angle) texels of depth.
inline constexpr float kNormalOffsetTexels = 1.0f;
inline constexpr float kConstantBiasTexels = 0.25f;
inline constexpr float kSlopeBiasTexels = 0.25f;
// The tangent plane's depth slope is clamped (about 87 degrees) so grazing receivers stay finite.
inline constexpr float kMaxSlope = 20.0f;
inline constexpr float kMinFacing = 1e-6f;

// What the blocker search of every row shares: the frame's constants.
struct BlockerSearchContext {
  const ReceiverPositions& receivers;  // camera pixels -> light view
  const ViewProjection& light;         // ShadowMapOutputs::lightView
  const Plane<float>& depthKey;        // ShadowMapOutputs::shadowMap's depth keys
  const glm::vec2* pattern;  // the taps in the unit disc (Vogel's spiral), tap 0 the centre
  size_t taps;
  glm::mat3 normalToLight;   // camera view -> light view, rigid: normals need no inverse transpose
  float texelX, texelY;      // orthographic: texel size in metres; perspective: per metre of depth
  float invTexelX, invTexelY;
  float tanAngularRadius;    // directional
  float lightRadius;         // spot, metres
  float maxBlockerDistance;  // metres
  NormalEncoding encoding;
};

// The tap pattern (docs/pipeline.md §Blocker search): Vogel's spiral in the unit disc, tap 0 the
// centre, `taps` in [1, kMaxBlockerSearchTaps].
std::vector<glm::vec2> BlockerSearchPattern(int taps);

// The context RunShadowMap's search runs with: `light` (PrepareLights order, world space) seen
// through map.lightView, receivers in that view, normals of the given encoding. The context refers
// to `receivers`, `map` and `pattern`, which must outlive it.
BlockerSearchContext MakeBlockerSearchContext(const ReceiverPositions& receivers, const ShadowMapOutputs& map,
                                              const PreparedLight& light, const std::vector<glm::vec2>& pattern,
                                              float maxBlockerDistance, NormalEncoding encoding);

// The receivers of G-buffer row `row`: returns how many of the `width` pixels of word 2 (view depth)
// have geometry, and widens [lo, hi] by their light-view (x, y, depth) positions (ReceiverPositions::At
// with depth = -z), each component + 0 first, so that -0 counts as +0 and the bounds do not depend on
// the order the pixels are visited in. The scalar definition (shadow_map.cpp) and its Highway twin
// (shadow_map_simd.cpp), equal on every target.
size_t ReceiverBoundsRowScalar(const uint32_t* word2, int width, const ReceiverPositions& positions,
                               const ReceiverPositions::Row& row, glm::vec3& lo, glm::vec3& hi);
size_t ReceiverBoundsRowSimd(const uint32_t* word2, int width, const ReceiverPositions& positions,
                             const ReceiverPositions::Row& row, glm::vec3& lo, glm::vec3& hi);

// RunShadowMap's blocker search on its own: every row of the G-buffer (words 1 and 2) into
// shadowTerm, in parallel row bands, with the row kernel `kernels` picks.
void RunBlockerSearch(const BlockerSearchContext& context, const GBuffer& gbuffer, Plane<uint32_t>& shadowTerm,
                      KernelPath kernels = KernelPath::kSimd);

// The blocker search's scalar row kernel, the definition a SIMD twin (passes/shadow_map_simd.cpp)
// must equal bit for bit: the PCSS blocker search (Fernando 2005, §3.1) of G-buffer row y, `width`
// pixels of words 1 (normal) and 2 (view depth), into shadowTerm[x] (PackShadowTerm; kShadowLit for
// background, for receivers outside the shadow map and where no tap finds a blocker).
void BlockerSearchRowScalar(const BlockerSearchContext& context, const uint32_t* word1, const uint32_t* word2, int y,
                            int width, uint32_t* shadowTerm);
void BlockerSearchRowSimd(const BlockerSearchContext& context, const uint32_t* word1, const uint32_t* word2, int y,
                          int width, uint32_t* shadowTerm);

}  // namespace ssgi
