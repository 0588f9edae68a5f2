// Direct light pass (DESIGN.md §5, docs/pipeline.md §Direct light): shades every G-buffer pixel with
// every light of the scene using core/brdf.h; the shadowed light's term is multiplied by its
// visibility from the shadow filter. Background pixels get the scene's background radiance. No ambient term.
#pragma once

#include "core/camera.h"
#include "core/gbuffer.h"
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
};

struct DirectLightParams {
  glm::vec3 background{0.0f};  // linear RGB radiance of pixels no geometry covers
};

struct DirectLightOutputs {
  Plane3<float> radiance;  // linear RGB radiance towards the camera, finite and >= 0
};

struct DirectLightStats {
  double ms = 0.0;
  size_t pixels = 0;
};

DirectLightStats RunDirectLight(const DirectLightInputs& in, const DirectLightParams& params,
                                DirectLightOutputs& out);

}  // namespace ssgi
