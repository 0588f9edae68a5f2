// The environment: light from infinitely far away, arriving from every direction no geometry
// blocks. It is what the camera sees where no geometry covers a pixel, and it lights every surface,
// as a world colour does in every physically based renderer (docs/design.md §2). A scene file's
// "environment" (docs/user-guide.md "Scene files").
//
// It is a light like any other to the Embree reference's path tracer, which samples it (Sample,
// Pdf) and weights those samples against BSDF sampling with multiple importance sampling (Veach
// 1997, "Robust Monte Carlo Methods for Light Transport Simulation", chapter 9). An environment
// kind with an uneven radiance (a sky, an HDR map) samples its bright parts more often, as pbrt-v4's
// ImageInfiniteLight does (Pharr et al., "Physically Based Rendering", 4th ed., §12.5.2), and keeps
// Pdf the density its Sample draws from.
#pragma once

#include <cmath>
#include <glm/glm.hpp>

#include "core/brdf.h"

namespace ssgi {

enum class EnvironmentKind {
  kConstant,  // the same radiance from every direction
};

// A direction drawn from an environment's sampling density.
struct EnvironmentSample {
  glm::vec3 direction;  // unit, world space: light arrives along -direction
  glm::vec3 radiance;   // Radiance(direction)
  float pdf;            // solid-angle density of `direction` (1/sr), > 0; Pdf(direction)
};

struct Environment {
  EnvironmentKind kind = EnvironmentKind::kConstant;
  glm::vec3 radiance{0.0f};  // kConstant: linear RGB radiance, W/(m^2 sr), each component >= 0

  // The radiance arriving along -direction, that is seen looking along `direction` (world space,
  // unit length).
  glm::vec3 Radiance(const glm::vec3& /*direction*/) const { return radiance; }
  bool IsBlack() const { return radiance == glm::vec3(0.0f); }

  // A direction from two uniforms in [0, 1), drawn with a density close to the radiance's
  // distribution over the sphere. kConstant: uniform over the sphere (pbrt-v4 §A.5.2,
  // SampleUniformSphere), density 1 / (4 pi): every direction carries the same radiance.
  EnvironmentSample Sample(float u1, float u2) const {
    const float z = 1.0f - 2.0f * u1;
    const float r = std::sqrt(std::fmax(0.0f, 1.0f - z * z));
    const float phi = 2.0f * kPi * u2;
    const glm::vec3 direction(r * std::cos(phi), r * std::sin(phi), z);
    return {direction, Radiance(direction), Pdf(direction)};
  }
  // The density Sample draws `direction` (unit) with.
  float Pdf(const glm::vec3& /*direction*/) const { return 1.0f / (4.0f * kPi); }
};

}  // namespace ssgi
