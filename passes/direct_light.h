// Direct light pass (docs/design.md §5, docs/pipeline.md §Direct light): shades every G-buffer pixel with
// every light of the scene using core/brdf.h; the shadowed light's term is multiplied by its
// visibility from the shadow filter. Background pixels get the scene's background radiance. No ambient term.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/kernel_path.h"
#include "core/lighting.h"
#include "core/plane.h"
#include "core/scene.h"

namespace ssgi {

struct DirectLightInputs {
  const GBuffer& gbuffer;
  const ViewProjection& view;  // the camera the G-buffer was rendered with
  const Scene& scene;          // the lights
  // The shadowed light (index in PrepareLights order) and its visibility in [0, 1] per pixel, from
  // a shadow filter; null when no light is shadowed. Other lights are unshadowed.
  const Plane<float>* lightVisibility = nullptr;
  size_t shadowedLight = 0;
  // Per light in PrepareLights order, whether to shade it (FramePlan::lightReaches: a light no
  // visible pixel faces adds exactly 0, so leaving it out changes no byte); null: every light.
  const std::vector<bool>* shadeLights = nullptr;
};

struct DirectLightParams {
  glm::vec3 background{0.0f};  // linear RGB radiance of pixels no geometry covers
};

struct DirectLightOutputs {
  // Linear RGB radiance towards the camera, sanitised (SanitizeRadiance): finite, in [0, kMaxRadiance].
  Plane3<float> radiance;
};

struct DirectLightStats {
  double ms = 0.0;
  size_t pixels = 0;
};

DirectLightStats RunDirectLight(const DirectLightInputs& in, const DirectLightParams& params,
                                DirectLightOutputs& out, KernelPath kernels = KernelPath::kSimd);

// What the shading of every row shares: the frame's constants.
struct DirectLightContext {
  const ViewProjection& view;
  const PreparedLight* lights;  // PrepareLights(scene, view.view): in view space
  size_t lightCount;
  size_t shadowedLight;  // the light a row's visibility applies to (DirectLightInputs::shadowedLight)
  NormalEncoding normalEncoding;
  glm::vec3 background;  // radiance of background pixels
};

// The direct light's scalar row kernel, the definition a SIMD twin (passes/direct_light_simd.cpp) must
// equal bit for bit: shades row y, `width` pixels of G-buffer words 0-2, with every light into
// red[x], green[x], blue[x]; visibility (null: no light shadowed) scales the shadowed light's term.
// Returns how many pixels had geometry.
size_t DirectLightRowScalar(const DirectLightContext& context, const uint32_t* word0, const uint32_t* word1,
                            const uint32_t* word2, const float* visibility, size_t y, int width, float* red,
                            float* green, float* blue);
// Its Highway twin (passes/direct_light_simd.cpp): lanes are pixels of the row.
size_t DirectLightRowSimd(const DirectLightContext& context, const uint32_t* word0, const uint32_t* word1,
                          const uint32_t* word2, const float* visibility, size_t y, int width, float* red,
                          float* green, float* blue);

}  // namespace ssgi
