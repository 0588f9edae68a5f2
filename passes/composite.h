// Composite pass (DESIGN.md §7-§8, docs/pipeline.md §Composite): the final linear HDR image,
// result = direct + indirect, where indirect = reflected radiance x specular weight x confidence x
// roughness fade:
// the cone-traced screen-space reflection (passes/ssr_cone.h), weighted by the split-sum specular
// term of the pixel's material and view angle (Karis 2013, core/brdf.h) and faded by the trace's confidence.
#pragma once

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/plane.h"

namespace ssgi {

struct CompositeInputs {
  const GBuffer& gbuffer;          // words 0 (albedo, metallic), 1 (normal, roughness), 2 (depth)
  const ViewProjection& view;
  const Plane3<float>& direct;     // linear RGB radiance
  const Plane3<float>& reflected;  // cone-traced radiance, 0 where nothing was hit
  const Plane<float>& confidence;  // [0, 1], 0 where nothing was hit
  float roughnessCutoff;           // the trace's: rougher pixels were not traced
};

// The reflection fades out linearly over the last kRoughnessFadeWidth of perceptual roughness below
// the trace's cut-off, so a material just under it does not end in a visible step.
inline constexpr float kRoughnessFadeWidth = 0.1f;

struct CompositeOutputs {
  Plane3<float> indirect;  // reflected x specular weight x confidence
  Plane3<float> result;    // direct + indirect
};

struct CompositeStats {
  double ms = 0.0;
  size_t pixels = 0;
};

CompositeStats RunComposite(const CompositeInputs& in, CompositeOutputs& out);

}  // namespace ssgi
