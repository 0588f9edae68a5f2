// The environment as the screen-space passes read it (docs/design.md §2, docs/pipeline.md
// §Environment lighting): converted once per frame (kept across frames while the environment does
// not change) into tables a pixel reads with multiplies, adds and one division, no libm:
//   - an octahedral map of the radiance (level 0: the background and mirror reflections) and its
//     GGX-prefiltered levels by roughness (the split-sum "LD" term, Karis 2013), for specular light;
//   - the irradiance as nine spherical-harmonic coefficients (Ramamoorthi & Hanrahan 2001), for
//     diffuse light.
// A constant environment is exact: every lookup returns its radiance.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/environment.h"
#include "core/plane.h"

namespace ssgi {

// The octahedral map (Engelhardt & Dachsbacher 2008; Cigolle et al. 2014, "A Survey of Efficient
// Representations for Independent Unit Vectors"), folded about world y so that the sky (y >= 0) is
// the inner diamond: d / (|x| + |y| + |z|) = p; where p.y < 0 the (x, z) quadrant folds outwards,
// (x, z) = ((1 - |p.z|) s(p.x), (1 - |p.x|) s(p.z)) with s(t) = t >= 0 ? 1 : -1; then
// (u, v) = (x, z) * 0.5 + 0.5 in [0, 1]^2.
glm::vec2 OctahedralEncode(const glm::vec3& direction);
// The unit direction of (u, v), the encode's inverse.
glm::vec3 OctahedralDecode(const glm::vec2& uv);

// One square octahedral level of `size` x `size` texels with a one-texel border on every side
// holding the texels across the map's seams (texel (-1, j) is texel (0, size - 1 - j), and so on),
// so a bilinear lookup never clamps: planes of (size + 2) x (size + 2).
struct OctahedralLevel {
  int size = 0;
  Plane3<float> texels;
};

struct EnvironmentLightingParams {
  int radianceSize = 256;     // level 0's side
  int prefilteredSize = 64;   // level 1's side; each further level halves, down to kMinLevelSize
  int prefilterSamples = 64;  // GGX directions per prefiltered texel (Hammersley)
};
inline constexpr int kEnvironmentLevels = 6;  // level k holds perceptual roughness k / 5
inline constexpr int kMinLevelSize = 8;

struct EnvironmentLighting {
  // A constant environment: every lookup below is `constantRadiance`, exactly, and the tables are
  // not made.
  bool constant = true;
  glm::vec3 constantRadiance{0.0f};
  std::array<OctahedralLevel, kEnvironmentLevels> levels;
  // Irradiance over pi, E(n) / pi, as nine RGB coefficients of the real SH basis (the l <= 2 bands,
  // already convolved with the clamped cosine): Lambert's albedo times this is the reflected
  // radiance.
  std::array<glm::vec3, 9> irradianceSh{};
  Environment source;  // what it was made from: a frame keeps it while this does not change
};

// Makes the tables of `environment` (scalar, deterministic: row bands of fixed size).
EnvironmentLighting PrepareEnvironmentLighting(const Environment& environment,
                                               const EnvironmentLightingParams& params = {});
// Whether `lighting` was made from `environment` and can be kept.
bool SameEnvironment(const EnvironmentLighting& lighting, const Environment& environment);

// The per-pixel reads, the scalar definitions (the passes' Highway twins follow them operation by
// operation; core/environment_lighting-inl.h):
// Radiance seen along the world-space unit `direction`: level 0, bilinear.
glm::vec3 EnvironmentRadiance(const EnvironmentLighting& lighting, const glm::vec3& direction);
// Prefiltered radiance towards `direction` for perceptual roughness r in [0, 1]: the two levels
// around r * 5, each bilinear, mixed linearly.
glm::vec3 PrefilteredEnvironment(const EnvironmentLighting& lighting, const glm::vec3& direction, float roughness);
// E(n) / pi for the world-space unit normal n, clamped to >= 0.
glm::vec3 EnvironmentIrradiance(const EnvironmentLighting& lighting, const glm::vec3& normal);

}  // namespace ssgi
