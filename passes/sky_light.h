// Sky light (docs/design.md §5, docs/pipeline.md §Sky light): the environment's diffuse light on
// every visible surface, diffuse = albedo (1 - metallic) E(n) / pi V(p, n), where E is the
// environment's irradiance (core/environment_lighting.h) and V the world-space sky visibility at the
// surface: how much of the sky the scene leaves open there, off screen included (a roof or an
// arcade ceiling the camera does not see still blocks the sky). It also writes `lit` = direct +
// diffuse: the radiance the diffuse bounce gathers and the colour pyramid blurs, so that surfaces
// only the sky lights are seen in reflections and bounce light too. The screen-space occlusion of
// the bounce pass (passes/bounce.h) multiplies `diffuse` in the composite; it is not in `lit`.
//
// V comes from a volume made once per scene (BuildSkyVisibility): the scene rasterized orthographically
// from kSkyDirections directions spread over the sphere, each cell centre of a grid over the scene
// tested against every map, and each cell's visibility kept as the four coefficients of its
// clamped-cosine convolution in the first two spherical-harmonic bands, so V(p, n) is a trilinear
// read and a dot product.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/environment_lighting.h"
#include "core/gbuffer.h"
#include "core/kernel_path.h"
#include "core/plane.h"
#include "core/scene.h"

namespace ssgi {

struct SkyVisibilityParams {
  int directions = 48;          // maps over the sphere (a Fibonacci spiral); 0: no volume, V = 1
  int mapSize = 256;            // texels per side of each map
  int cellsOnLongestAxis = 48;  // the grid's resolution along the scene's longest side
};

// V(p, n) = k0 + kx n.x + ky n.y + kz n.z at each cell centre, clamped to [0, 1] when read.
struct SkyVisibilityVolume {
  int cellsX = 0, cellsY = 0, cellsZ = 0;
  glm::vec3 origin{0.0f};     // the grid's low corner, world space
  glm::vec3 extent{0.0f};     // the scene's bounds: origin + cellSize to that + extent
  float cellSize = 1.0f;      // metres
  float inverseCellSize = 1.0f;
  // Per cell (x fastest, then y, then z), the four coefficients k0, kx, ky, kz, interleaved.
  std::vector<float> coefficients;
  uint64_t meshHash = 0;  // the scene it was made for (MeshGeometryHash)
  SkyVisibilityParams params;
};

// The volume's grid for `scene`, without its coefficients (docs/pipeline.md §Sky light): cubic
// cells of the scene's longest side over cellsOnLongestAxis, a cell of margin on every side, so the
// grid's outer cells lie outside the scene.
SkyVisibilityVolume SkyVisibilityGrid(const Scene& scene, const SkyVisibilityParams& params);
// The volume's map directions, towards the sky: a Fibonacci spiral over the sphere, y = 1 - 2 (i +
// 0.5) / count, phi = 2.39996322972865332 i, in double, each component rounded once.
std::vector<glm::vec3> SkyVisibilityDirections(int count);
// What the volume for `scene` takes (its coefficients), and what making it holds besides: each
// thread's map and rasterizer set-up, and every map's cell visibility; 0 for 0 directions, where the
// frame makes no volume.
size_t SkyVisibilityBytes(const Scene& scene, const SkyVisibilityParams& params);
size_t SkyVisibilityBuildBytes(const Scene& scene, const SkyVisibilityParams& params);

// The volume for `scene` (deterministic: the maps in parallel, each cell's sum in direction order).
SkyVisibilityVolume BuildSkyVisibility(const Scene& scene, const SkyVisibilityParams& params);
// V(p, n) for a world-space point and unit normal: the volume read at p + n cellSize / 2, so that a
// surface reads the cells in front of it, not those inside the wall it lies on.
float SkyVisibility(const SkyVisibilityVolume& volume, const glm::vec3& position, const glm::vec3& normal);

// Where a point and normal read a volume of the grid (the visibility's, and the interreflection's of
// passes/world_bounce.h, which shares it): the eight cells around p + n cellSize / 2 (corner bit 0:
// the next cell in x, bit 1 in y, bit 2 in z; as offsets of their first coefficient) and the
// trilinear weights.
struct VolumeSample {
  size_t corner[8];
  float f[3];
  glm::vec3 normal;
};
VolumeSample SampleVolume(const SkyVisibilityVolume& volume, const glm::vec3& position, const glm::vec3& normal);
// k0 + k.n of a table of four coefficients per cell, read trilinearly (x, then y, then z), unclamped.
float ReadVolume(const float* coefficients, const VolumeSample& sample);
// The same cells and weights, k0 + k.w towards another unit direction w (the mirror direction).
float ReadVolumeToward(const float* coefficients, const VolumeSample& sample, const glm::vec3& direction);

struct WorldBounceVolume;  // passes/world_bounce.h

struct SkyLightInputs {
  const GBuffer& gbuffer;                   // words 0 (albedo, metallic), 1 (normal), 2 (depth)
  const ViewProjection& view;               // perspective
  const EnvironmentLighting& environment;
  const SkyVisibilityVolume* visibility;    // null: the sky is open everywhere (V = 1)
  const Plane3<float>& direct;              // linear RGB radiance
  // The scene's light interreflected off screen, on the visibility volume's grid (null: none; needs
  // `visibility`): diffuse gains albedo (1 - metallic) max(E_w(p, n) / pi, 0) per channel.
  const WorldBounceVolume* interreflection = nullptr;
};

struct SkyLightParams {};

// May hold an earlier frame's planes: those of the image's size are overwritten.
struct SkyLightOutputs {
  Plane3<float> diffuse;   // albedo (1 - metallic) E(n) / pi V; 0 on background
  Plane<float> visibility;  // V(p, n) in [0, 1]; 1 on background
  Plane3<float> lit;       // direct + diffuse
  // With the interreflection volume (else empty): max(E_w(p, r) / pi, 0) per channel towards the
  // mirror direction r, the light the surfaces around send a glossy reflection that the trace does
  // not see; 0 on background.
  Plane3<float> reflected;
};

struct SkyLightStats {
  double ms = 0.0;
  size_t pixels = 0;
};

SkyLightStats RunSkyLight(const SkyLightInputs& in, const SkyLightParams& params, SkyLightOutputs& out,
                          KernelPath kernels = KernelPath::kSimd);

// What every row shares.
struct SkyLightContext {
  glm::mat4 viewToWorld;
  NormalEncoding normalEncoding;
  const PixelRayTables& rays;
  const EnvironmentLighting& environment;
  const SkyVisibilityVolume* visibility;
  const WorldBounceVolume* interreflection;  // only with `visibility`
};

struct SkyLightRow {
  const uint32_t* word0;
  const uint32_t* word1;
  const uint32_t* word2;
  const float* direct[3];
  float* diffuse[3];
  float* visibility;
  float* lit[3];
  float* reflected[3];  // null without the interreflection volume
};

// The definition (scalar) and its Highway twin (passes/sky_light_simd.cpp), equal bit for bit.
void SkyLightRowScalar(const SkyLightContext& context, const SkyLightRow& row, size_t y, int width);
void SkyLightRowSimd(const SkyLightContext& context, const SkyLightRow& row, size_t y, int width);

}  // namespace ssgi
