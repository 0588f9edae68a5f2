// Shadow map and PCSS blocker search (DESIGN.md §3 word 3, §4, §5; docs/pipeline.md §Shadow map and
// blocker search). For one shadow-casting light:
//  1. rasterizes the scene's depth from the light with the G-buffer's rasterizer (depth only, both
//     faces): orthographic for a directional light, fitted to the receivers the camera sees and
//     pulled back to every caster of the scene; perspective along the cone axis for a spot light;
//  2. runs the blocker search of Percentage-Closer Soft Shadows (Fernando 2005) for every G-buffer
//     pixel, with a normal-offset receiver and a receiver-plane depth test, and writes the result as
//     the G-buffer's shadow term (word 3, PackShadowTerm).
// Both faces of every triangle are drawn; cut-out (map_d) casters are alpha tested.
// The frame runs it once per shadow-casting light; G-buffer word 3 holds the term of the FIRST
// shadow-casting light (ShadowCastingLights(scene).front()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/plane.h"
#include "core/raster.h"
#include "core/scene.h"

namespace ssgi {

inline constexpr int kMaxBlockerSearchTaps = 256;

struct ShadowMapParams {
  int resolution = 2048;  // shadow map width and height in texels, [1, kMaxImageSize]
  // Blocker-search taps per pixel, [1, kMaxBlockerSearchTaps], including the centre tap (tap 0).
  int blockerSearchTaps = 16;
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
// normally the G-buffer's own word[3] (the pass never reads word 3).
ShadowMapStats RunShadowMap(const ShadowMapInputs& in, const ShadowMapParams& params, ShadowMapOutputs& out,
                            Plane<uint32_t>& shadowTerm);

// Indices (PrepareLights order) of the lights that cast shadows, in that order. The first one is the
// light whose shadow term the G-buffer's word 3 holds.
std::vector<size_t> ShadowCastingLights(const Scene& scene);

}  // namespace ssgi
