// The Embree ground truth (docs/design.md §10, docs/pipeline.md §Embree reference), ray traced with
// Embree 3 over the same world-space mesh, materials, textures, BRDF (core/brdf.h), lights
// (core/lighting.h) and environment (core/environment.h) as the screen-space pipeline. Two light
// transports:
//
// - kFull (`ssgi reference`'s default): a unidirectional path tracer of full light transport
//   (Pharr et al., "Physically Based Rendering", 4th ed., ch. 13, PathIntegrator): the BRDF sampled
//   by lobe (cosine-weighted Lambert or GGX visible normals, Heitz 2018), each light over its real
//   extent and the environment sampled at every vertex, both strategies weighted by the power
//   heuristic (Veach 1997, ch. 9), Russian roulette after a few bounces, primary rays jittered over
//   the pixel (box filter) unless `pixelCentre`.
// - kPaper: the restricted transport the screen-space pipeline approximates, for per-pass metrics
//   that compare like with like: one ray through each pixel centre, direct light with area-light
//   soft shadows (every light sampled over its real extent, one shadow ray per sample, every
//   shadow-casting light), and one GGX specular bounce of direct light traced in world space
//   (so off-screen and hidden surfaces reflect too), sampled from the distribution of visible
//   normals.
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

enum class ReferenceTransport {
  kFull,   // every path of light: direct, environment, interreflections (the ground truth)
  kPaper,  // direct light + one GGX specular bounce of direct light (what the pipeline models)
};

// Bounces after which more change nothing visible on the bundled scenes (docs/pipeline.md
// §Embree reference, "Path length"); Russian roulette ends most paths long before.
inline constexpr int kDefaultReferenceBounces = 16;

struct ReferenceParams {
  int width = kDefaultImageSide;  // image size in pixels, as the frame it is compared with
  int height = kDefaultImageSide;
  // What a ray that leaves the scene sees (the frame's environment). kFull: a light, sampled and hit
  // by paths like the scene's lights. kPaper: seen only by the camera rays that miss and the bounce
  // rays.
  Environment environment;
  ReferenceTransport transport = ReferenceTransport::kFull;
  uint32_t seed = 0;  // selects the sample streams; the same seed gives the same bytes

  // kPaper.
  int lightSamples = 16;       // per light per pixel for the direct light, >= 1
  int bounceSamples = 16;      // GGX directions per pixel for the specular bounce, >= 0 (0: no bounce)
  int bounceLightSamples = 1;  // per light at each bounce hit, >= 1

  // kFull.
  int samplesPerPixel = 16;  // paths per pixel, >= 1
  // Reflections after the first hit, >= 0: a path scatters at most bounces + 1 times (0: the
  // lights' and the environment's light reflected once, at the first hit).
  int bounces = kDefaultReferenceBounces;
  // One primary ray through the pixel centre instead of rays spread over the pixel (a box filter),
  // for metrics that pair the reference's pixels with a frame's one to one.
  bool pixelCentre = false;
};

// The CLI's one quality knob (`--spp N`): kFull, N paths per pixel; kPaper, N samples per pixel for
// both the direct light and the bounce.
inline ReferenceParams ReferenceParamsForSpp(int spp, ReferenceTransport transport = ReferenceTransport::kFull) {
  ReferenceParams params;
  params.transport = transport;
  params.samplesPerPixel = spp;
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
  size_t paths = 0;       // kFull: primary rays traced for paths (samplesPerPixel per pixel)
};

// Every plane has the params' size. Radiance is linear RGB towards the camera (W/(m^2 sr)),
// finite and >= 0, pixel centres as in core/camera.h. kFull averages its paths over the pixel
// (or through its centre with pixelCentre); depth and lightVisibility always come from the ray
// through the pixel centre.
struct ReferenceOutputs {
  // kFull: the scene's lights' light reflected at the first hit; the environment where the camera
  // ray leaves the scene. kPaper: the same with every light sample shadowed; background pixels:
  // the background.
  Plane3<float> direct;
  // kFull: everything else: the environment's light on surfaces and every interreflection.
  // kPaper: the specular bounce of direct light; background pixels: 0.
  Plane3<float> indirect;
  Plane3<float> result;  // direct + indirect
  // kFull: the estimated variance of each pixel's `result`, the sample variance of its paths over
  // their count (so its square root is the Monte Carlo standard error). kPaper: 0.
  Plane3<float> resultVariance;
  // Fraction of the light samples of the first shadow-casting light (PrepareLights order) whose
  // shadow ray is unoccluded, in [0, 1]; 1 for background and when no light casts shadows. The
  // ground truth of the shadow filter's visibility. kFull: samplesPerPixel samples at the
  // pixel-centre hit; kPaper: lightSamples.
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
// params' environment, in params.transport. Parallel over fixed bands of rows (core/parallel.h).
ReferenceOutputs RenderReference(const Scene& scene, const ReferenceParams& params,
                                 const ReferenceProgress& progress = nullptr);

}  // namespace ssgi
