// The Embree ground truth (docs/design.md §10, docs/pipeline.md §Embree reference): the light transport
// the screen-space pipeline approximates, ray traced with Embree 3 over the same world-space mesh,
// materials, textures, BRDF (core/brdf.h) and lights (core/lighting.h):
//
// - primary visibility: one ray through each pixel centre of the raster path's camera (no
//   antialiasing, so every pixel compares one to one with the G-buffer);
// - direct light with area-light soft shadows: every light sampled over its real extent (the
//   directional light's cone of directions, the spot light's emitter disc), one shadow ray per
//   sample, for every shadow-casting light (the screen-space path shadows only the first);
// - one GGX specular bounce of direct light, traced in world space (so off-screen and hidden
//   surfaces reflect too), sampled from the distribution of visible normals (Heitz 2018).
//
// Monte Carlo with independent samples from a per-pixel PCG stream (O'Neill 2014), so the error
// falls as 1/sqrt(samples) and the output is the same bytes at any thread count and every run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

#include "core/plane.h"
#include "core/scene.h"

namespace ssgi {

struct ReferenceParams {
  int width = kDefaultImageSide;  // image size in pixels, as the frame it is compared with
  int height = kDefaultImageSide;
  // What a ray that leaves the scene sees (the frame's environment): here only the camera rays that
  // miss and the bounce rays see it.
  Environment environment;
  int lightSamples = 16;       // per light per pixel for the direct light, >= 1
  int bounceSamples = 16;      // GGX directions per pixel for the specular bounce, >= 0 (0: no bounce)
  int bounceLightSamples = 1;  // per light at each bounce hit, >= 1
  uint32_t seed = 0;           // selects the sample streams; the same seed gives the same bytes
};

// The CLI's one quality knob (`--spp N`): N samples per pixel for both the direct light and the
// bounce.
inline ReferenceParams ReferenceParamsForSpp(int spp) {
  ReferenceParams params;
  params.lightSamples = spp;
  params.bounceSamples = spp;
  return params;
}

struct ReferenceStats {
  double buildMs = 0.0;   // Embree device and BVH
  size_t bvhBytes = 0;    // the most memory Embree's device held: the BVH and its copy of the mesh
  double traceMs = 0.0;   // every ray and the shading
  size_t coveredPixels = 0;
  size_t rays = 0;        // primary + shadow + bounce rays traced
};

// Every plane has the params' size. Radiance is linear RGB towards the camera (W/(m^2 sr)),
// finite and >= 0, pixel centres as in core/camera.h.
struct ReferenceOutputs {
  Plane3<float> direct;         // direct light with area soft shadows; background pixels: the background
  Plane3<float> indirect;       // the specular bounce of direct light; background pixels: 0
  Plane3<float> result;         // direct + indirect
  // Fraction of the light samples of the first shadow-casting light (PrepareLights order) whose
  // shadow ray is unoccluded, in [0, 1]; 1 for background and when no light casts shadows. The
  // ground truth of the shadow filter's visibility.
  Plane<float> lightVisibility;
  Plane<float> depth;           // view depth d (metres) of the primary hit, kBackgroundDepth (+inf) for none
  ReferenceStats stats;
};

// What RenderReference allocates for this scene and these params: its output planes and Embree's
// device (the BVH, about kReferenceBvhBytesPerTriangle a triangle, measured with Embree's memory
// monitor on the bundled and third-party scenes, with a margin).
inline constexpr size_t kReferenceBvhBytesPerTriangle = 200;
size_t EstimateReferenceMemory(const Scene& scene, const ReferenceParams& params);

// Called after each finished band of rows with the number of rows done so far and the total. Calls
// come from worker threads but never overlap, and rowsDone strictly increases. Progress never
// affects the output.
using ReferenceProgress = std::function<void(size_t rowsDone, size_t rows)>;

// Renders the reference at params.width x height with the scene's camera and lights and the
// params' background. Parallel over fixed bands of rows (core/parallel.h).
ReferenceOutputs RenderReference(const Scene& scene, const ReferenceParams& params,
                                 const ReferenceProgress& progress = nullptr);

}  // namespace ssgi
