// World-space interreflection volume (docs/pipeline.md §Sky light, "Interreflection beyond the
// screen"): the diffuse light that reaches a point from the scene's own surfaces, off screen
// included, which neither the screen-space bounce (passes/bounce.h, on-screen surfaces within its
// radius) nor the sky light (passes/sky_light.h, the sky alone) gives. Indoors it is most of the
// light in shadow: a sunlit floor lighting an arcade's ceiling, which lights its walls.
//
// Made once per scene, lights and environment, on the sky visibility volume's grid: from each cell
// centre, rays along the volume's Fibonacci directions (Embree, core/reference/ray_tracer.h) find
// the first surface; its radiance towards the cell is its diffuse albedo over pi times the light
// reaching it: every light (with a shadow ray where the light casts shadows) and the sky's
// irradiance under the sky visibility volume. The cell keeps the clamped-cosine convolution of
// those radiances in the first two spherical-harmonic bands, as the visibility volume does, so a
// pixel reads E(p, n) / pi as a trilinear read and a dot product per channel. Further bounces
// follow the radiosity of an enclosure: a cell that sees surfaces over a share o of its directions,
// of mean diffuse albedo rho, gets the first bounce times 1 / (1 - rho o), the sum of the light
// going round that enclosure again and again (the progressive radiosity's ambient term, Cohen et al.
// 1988, per cell instead of per scene).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/environment.h"
#include "core/environment_lighting.h"
#include "core/lighting.h"
#include "core/scene.h"
#include "passes/sky_light.h"

namespace ssgi {

struct WorldBounceParams {
  int directions = 64;  // rays from each cell centre (a Fibonacci spiral); 0: no volume
};

// The most of a cell's light that goes round again: rho o is clamped to this, so a closed box of
// white walls stays finite.
inline constexpr float kWorldBounceMaxReflected = 0.9f;

// A cell more than a quarter of whose rays meet the back of a one-sided surface lies inside a wall:
// it takes its neighbours' light instead of the none it sees.
inline constexpr int kWorldBounceInsideShare = 4;

struct WorldBounceVolume {
  // Per channel (R, G, B), per cell of the sky visibility volume's grid (x fastest, then y, then z),
  // the four coefficients k0, kx, ky, kz of E(n) / pi = k0 + k.n (clamped to >= 0 when read).
  std::array<std::vector<float>, 3> coefficients;
  // What it was made from: a frame keeps it while these hold.
  uint64_t meshHash = 0;
  std::vector<PreparedLight> lights;
  Environment environment;
  SkyVisibilityParams grid;
  WorldBounceParams params;
};

// A volume of zero coefficients on `sky`'s grid, stamped with what it is made for (`sky`'s mesh hash
// and grid, the scene's lights, `environment`, `params`): what BuildWorldBounce fills, and what a
// volume taken from a dump is read into.
WorldBounceVolume EmptyWorldBounce(const Scene& scene, const SkyVisibilityVolume& sky, const Environment& environment,
                                   const WorldBounceParams& params);
// The volume for `scene` on `sky`'s grid (sky: the scene's sky visibility volume, which also
// shadows the sky's light on the surfaces the rays hit). Deterministic: cells in parallel, each
// cell's sums in direction order.
WorldBounceVolume BuildWorldBounce(const Scene& scene, const SkyVisibilityVolume& sky,
                                   const EnvironmentLighting& environment, const WorldBounceParams& params);
// Whether `volume` was made for these and can be kept.
bool WorldBounceHolds(const WorldBounceVolume& volume, const Scene& scene, const SkyVisibilityVolume& sky,
                      const EnvironmentLighting& environment, const WorldBounceParams& params);
// Its coefficients' bytes, 0 without one.
size_t WorldBounceBytes(const Scene& scene, const SkyVisibilityParams& grid, const WorldBounceParams& params);
// What making it holds besides: Embree's BVH and mesh (core/reference/reference.h's estimate per
// triangle), the cells' masks and the coefficients' copy the inside cells are filled from.
size_t WorldBounceBuildBytes(const Scene& scene, const SkyVisibilityParams& grid, const WorldBounceParams& params);

}  // namespace ssgi
