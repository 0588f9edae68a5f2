// The metallic-roughness BRDF every path shares (docs/design.md §5), the screen-space passes and the
// Embree reference alike: Lambert diffuse + Cook-Torrance specular with the GGX distribution,
// height-correlated Smith visibility and Schlick Fresnel, F0 = mix(0.04, albedo, metallic), as in
// Filament's "Physically Based Rendering in Filament" §4; and the split-sum DFG table (Karis 2013,
// "Real Shading in Unreal Engine 4") that weights the traced reflections in the composite.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/glm.hpp>

namespace ssgi {

inline constexpr float kPi = 3.14159265358979323846f;
// GGX alpha below this makes D a near-delta that a point evaluation can't resolve (Filament's fp32
// minimum perceptual roughness 0.045, squared).
inline constexpr float kMinGgxAlpha = 0.045f * 0.045f;

struct SurfaceMaterial {
  glm::vec3 albedo;  // linear base colour
  float metallic;
  float roughness;   // perceptual
};

inline float GgxDistribution(float nDotH, float alpha) {
  const float a2 = alpha * alpha;
  const float f = nDotH * nDotH * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * f * f);
}

// V = G / (4 n.l n.v), height-correlated Smith for GGX (Heitz 2014).
inline float SmithGgxCorrelatedVisibility(float nDotV, float nDotL, float alpha) {
  const float a2 = alpha * alpha;
  const float ggxV = nDotL * std::sqrt(nDotV * nDotV * (1.0f - a2) + a2);
  const float ggxL = nDotV * std::sqrt(nDotL * nDotL * (1.0f - a2) + a2);
  return 0.5f / (ggxV + ggxL);
}

// V n.l, at most 0.5 / alpha: V above divided through by n.l, so that it stays finite where n.l and
// n.v are both so small (denormal) that V's denominator underflows to 0. n.l > 0.
inline float SmithGgxCorrelatedVisibilityCosine(float nDotV, float nDotL, float alpha) {
  const float a2 = alpha * alpha;
  const float lambdaV = std::sqrt(nDotV * nDotV * (1.0f - a2) + a2);
  const float lambdaL = std::sqrt(nDotL * nDotL * (1.0f - a2) + a2);
  return 0.5f / (lambdaV + (nDotV / nDotL) * lambdaL);
}

inline glm::vec3 SchlickFresnel(float vDotH, const glm::vec3& f0) {
  const float m = 1.0f - vDotH;
  const float m2 = m * m;
  return f0 + (glm::vec3(1.0f) - f0) * (m2 * m2 * m);
}

inline glm::vec3 SpecularF0(const SurfaceMaterial& m) { return glm::mix(glm::vec3(0.04f), m.albedo, m.metallic); }

// BRDF times n.l for unit vectors n (normal), v (to viewer), l (to light), a point light's or one
// sample of an area light's (the screen-space passes' area light is DiskLightBrdfCosine,
// core/lighting.h). `alpha` is the specular lobe's GGX alpha, clamped to kMinGgxAlpha. Returns 0
// when l or v is below the surface.
inline glm::vec3 BrdfCosine(const SurfaceMaterial& m, float alpha, const glm::vec3& n, const glm::vec3& v,
                            const glm::vec3& l) {
  const float nDotL = glm::dot(n, l);
  const float nDotV = glm::dot(n, v);
  if (!(nDotL > 0.0f) || !(nDotV > 0.0f)) return glm::vec3(0.0f);
  glm::vec3 h = v + l;
  const float hLength = glm::length(h);
  h = hLength > 0.0f ? h / hLength : n;
  const float nDotH = std::clamp(glm::dot(n, h), 0.0f, 1.0f);
  const float vDotH = std::clamp(glm::dot(v, h), 0.0f, 1.0f);
  alpha = std::max(alpha, kMinGgxAlpha);
  const glm::vec3 specular = SchlickFresnel(vDotH, SpecularF0(m)) *
                             (GgxDistribution(nDotH, alpha) * SmithGgxCorrelatedVisibility(nDotV, nDotL, alpha));
  const glm::vec3 diffuse = m.albedo * ((1.0f - m.metallic) / kPi);
  return (diffuse + specular) * nDotL;
}

// Split-sum DFG (Karis 2013): for GGX with height-correlated Smith visibility (above) and
// Schlick Fresnel, the directional albedo = F0 * A + B. Tabulated at n.v = i / (kDfgSize - 1) and
// perceptual roughness = j / (kDfgSize - 1), alpha = max(roughness^2, kMinGgxAlpha), each entry the
// mean over kDfgSamples GGX-importance-sampled half vectors on the Hammersley set; A + B is
// rescaled to <= 1 where quadrature error exceeds energy conservation.
inline constexpr int kDfgSize = 32;
inline constexpr int kDfgSamples = 1024;
struct DfgTable {
  std::array<glm::vec2, kDfgSize * kDfgSize> ab;  // (A, B) at [j * kDfgSize + i], in [0, 1], A + B <= 1
};
DfgTable BuildDfgTable();
// The table as the passes read it: BuildDfgTable's, shipped precomputed in core/dfg_table.inc.
const DfgTable& ShippedDfgTable();
// F0 * A + B for nDotV, roughness (perceptual) in [0, 1] (clamped), bilinear in the shipped table.
glm::vec3 SpecularWeight(glm::vec3 f0, float nDotV, float roughness);
// The table SpecularWeight reads, for SIMD kernels that look it up and so give the same values: its
// kDfgSize^2 A values, then its B values, each at [j * kDfgSize + i], so that a row of one of them
// lies in consecutive floats.
const float* DfgTableForKernels();

}  // namespace ssgi
