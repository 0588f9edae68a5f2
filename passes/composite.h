// Composite pass (docs/design.md §7-§8, docs/pipeline.md §Composite): the final linear HDR image,
// result = direct + indirect, where indirect is the specular light the direct light pass does not
// give: the cone-traced screen-space reflection (passes/ssr_cone.h), weighted by the split-sum
// specular term of the pixel's material and view angle (Karis 2013, core/brdf.h) and by the trace's
// confidence and the roughness fade; and, where the sky light runs, the environment prefiltered
// towards the reflected direction for the share the trace did not see (a miss, low confidence, a
// surface rougher than the cut-off), weighted alike and by the sky's visibility, and for the same
// share the light of the surfaces around from the interreflection volume (what the sky's visibility
// took away; passes/sky_light.h, SkyLightOutputs::reflected). With the sky light
// `direct` is its `lit` image (direct + the sky's diffuse light). Where the diffuse bounce runs
// (passes/bounce.h), indirect also holds its light on the diffuse albedo, and its ambient visibility
// darkens the sky's diffuse light, which `lit` holds at full strength: result = (lit + skyDiffuse
// (visibility - 1)) + indirect.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/camera.h"
#include "core/environment_lighting.h"
#include "core/gbuffer.h"
#include "core/kernel_path.h"
#include "core/plane.h"
#include "core/tile_mask.h"

namespace ssgi {

struct CompositeInputs {
  const GBuffer& gbuffer;          // words 0 (albedo, metallic), 1 (normal, roughness), 2 (depth)
  const ViewProjection& view;
  const Plane3<float>& direct;     // linear RGB radiance
  // Null where the frame traced no reflections: no pixel has a hit.
  const Plane3<float>* reflected;  // cone-traced radiance, 0 where nothing was hit
  const Plane<float>* confidence;  // [0, 1], 0 where nothing was hit
  float roughnessCutoff;           // the trace's: rougher pixels were not traced
  // FramePlan::reflectionTiles, or null: its 32x32 tiles hold every pixel smoother than the cut-off,
  // and the others, where the indirect light is 0 (reflected and confidence finite and >= 0, as
  // the cone and the trace give them), are stored as such without reading the G-buffer.
  const TileMask* tiles = nullptr;
  // The sky's specular light, where the sky light runs (null: none): the environment and the sky's
  // visibility (passes/sky_light.h). Every pixel then has indirect light: `tiles` must be null.
  const EnvironmentLighting* environment = nullptr;
  const Plane<float>* skyVisibility = nullptr;
  // With the sky light's interreflection volume (else null): its light towards the mirror
  // direction (SkyLightOutputs::reflected), which fills the share the trace did not see beside the
  // environment's.
  const Plane3<float>* skyReflected = nullptr;
  // The diffuse bounce, where it runs (null: none): its radiance E / pi (passes/bounce.h), which
  // indirect gains times the diffuse albedo, albedo (1 - metallic) as the direct light's Lambert
  // term takes it. Every pixel then has indirect
  // light: `tiles` must be null.
  const Plane3<float>* bounce = nullptr;
  // With the bounce and the sky light both (else both null): the sky's diffuse light (in `direct`
  // already, passes/sky_light.h) and the bounce's ambient visibility, which scales it:
  // the base image is direct + skyDiffuse (visibility - 1).
  const Plane3<float>* skyDiffuse = nullptr;
  const Plane<float>* ambientVisibility = nullptr;
  // Whether out.indirect is written: not where nothing reads the indirect term apart from the result.
  bool keepIndirect = true;
};

// The reflection fades out linearly over the last kRoughnessFadeWidth of perceptual roughness below
// the trace's cut-off, so a material just under it does not end in a visible step.
inline constexpr float kRoughnessFadeWidth = 0.1f;

// out.result may be in.direct's planes and out.indirect in.reflected's (the frame's memory-saving
// mode): each pixel is read before it is written.
struct CompositeOutputs {
  Plane3<float> indirect;  // reflected x specular weight x confidence (+ the sky's, + the bounce's)
  Plane3<float> result;    // direct (darkened where the bounce's visibility is below 1) + indirect
};

struct CompositeStats {
  double ms = 0.0;
  size_t pixels = 0;
};

CompositeStats RunComposite(const CompositeInputs& in, CompositeOutputs& out, KernelPath kernels = KernelPath::kSimd);

// What the composite of every row shares: the frame's constants (as in CompositeInputs).
struct CompositeContext {
  const ViewProjection& view;
  NormalEncoding normalEncoding;
  float roughnessCutoff;
  // The outputs are the inputs' planes (result = direct, indirect = reflected): a pixel the trace
  // did not hit already holds its outputs there (the direct light is sanitised, so direct + 0 is
  // direct, and the cone wrote 0), so it is not written again. Not with the sky's light or the
  // bounce.
  bool inPlace = false;
  const EnvironmentLighting* environment = nullptr;  // CompositeInputs::environment
  glm::mat3 viewToWorld{1.0f};                       // rotates the reflected direction into the world
};

// One row of every buffer the composite reads and writes, each at the row's pixel 0; RGB as three
// channel rows.
struct CompositeRow {
  const uint32_t* word0;
  const uint32_t* word1;
  const uint32_t* word2;
  const float* confidence;     // null: no reflections, confidence 0
  const float* skyVisibility;  // null without the sky's light
  const float* skyReflected[3];  // null without the interreflection volume
  const float* direct[3];
  const float* reflected[3];
  float* indirect[3];  // null: not kept (CompositeInputs::keepIndirect)
  float* result[3];
  const float* bounce[3];          // null without the bounce
  const float* skyDiffuse[3];      // null unless both the bounce and the sky's light
  const float* ambientVisibility;  // likewise
};

// The composite's scalar row kernel, the definition a SIMD twin (passes/composite_simd.cpp) must
// equal bit for bit: indirect and result of the pixels [xBegin, xEnd) of row y.
void CompositeRowScalar(const CompositeContext& context, const CompositeRow& row, size_t y, int xBegin, int xEnd);
// Its Highway twin (passes/composite_simd.cpp): lanes are pixels of the row.
void CompositeRowSimd(const CompositeContext& context, const CompositeRow& row, size_t y, int xBegin, int xEnd);

}  // namespace ssgi
