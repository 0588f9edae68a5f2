// Light sources seen from a shaded point (docs/design.md §5): one evaluation for the screen-space passes
// and the Embree reference. A light is prepared once per frame in the space the caller shades in
// (view space for the passes, world space for the reference), then evaluated per point.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "core/scene.h"

namespace ssgi {

struct LightAtPoint {
  glm::vec3 toLight;       // unit vector from the point to the light's centre
  glm::vec3 irradiance;    // W/m^2 on a surface facing the light, before shadowing
  float tanAngularRadius;  // tangent of the half-angle the emitter subtends at the point
};

struct PreparedLight {
  bool isSpot = false;
  glm::vec3 position{0.0f};   // spot: emitter centre
  glm::vec3 direction{0.0f};  // unit; directional: travel direction; spot: cone axis
  glm::vec3 power{0.0f};      // directional: irradiance (W/m^2); spot: intensity (W/sr)
  float tanAngularRadius = 0.0f;  // directional
  float radius = 0.0f;            // spot
  float cosOuter = 0.0f, coneScale = 1.0f;
};

// `toSpace` maps world space to the shading space; it must be rigid (rotation + translation).
inline PreparedLight Prepare(const DirectionalLight& light, const glm::mat4& toSpace) {
  PreparedLight p;
  p.direction = glm::normalize(glm::mat3(toSpace) * light.direction);
  p.power = light.irradiance;
  p.tanAngularRadius = std::tan(glm::radians(light.angularDiameterDegrees) * 0.5f);
  return p;
}

inline PreparedLight Prepare(const SpotLight& light, const glm::mat4& toSpace) {
  PreparedLight p;
  p.isSpot = true;
  p.position = glm::vec3(toSpace * glm::vec4(light.position, 1.0f));
  p.direction = glm::normalize(glm::mat3(toSpace) * light.direction);
  p.power = light.intensity;
  p.radius = light.radius;
  p.cosOuter = std::cos(glm::radians(light.outerConeDegrees));
  const float cosInner = std::cos(glm::radians(light.innerConeDegrees));
  p.coneScale = 1.0f / std::max(cosInner - p.cosOuter, 1e-4f);
  return p;
}

// Spot lights: smooth cone falloff between the inner and outer half-angles (Filament's spot
// attenuation, squared) and the inverse square of the distance, kept at least the emitter radius.
inline LightAtPoint Evaluate(const PreparedLight& light, const glm::vec3& point) {
  if (!light.isSpot) return {-light.direction, light.power, light.tanAngularRadius};
  const glm::vec3 offset = light.position - point;
  const float distance2 = glm::dot(offset, offset);
  const float distance = std::sqrt(distance2);
  LightAtPoint out;
  out.toLight = distance > 0.0f ? offset / distance : -light.direction;
  const float cone = std::clamp((glm::dot(-out.toLight, light.direction) - light.cosOuter) * light.coneScale, 0.0f, 1.0f);
  out.irradiance = light.power * (cone * cone / std::max(distance2, std::max(light.radius * light.radius, 1e-8f)));
  out.tanAngularRadius = distance > light.radius ? light.radius / distance : 1.0f;
  return out;
}

// GGX alpha widened by the light's angular size, so a mirror-like surface reflects a highlight of
// roughly the emitter's size instead of a single bright pixel (Karis 2013, "Real Shading in Unreal
// Engine 4", sphere lights: alpha' = saturate(alpha + radius / (2 distance))).
inline float WidenedAlpha(float alpha, float tanAngularRadius) {
  return std::min(1.0f, alpha + 0.5f * tanAngularRadius);
}

// Every light of a scene, prepared in one space; directional lights first, then spots, each in
// scene order (light indices in per-light buffers follow this order).
inline std::vector<PreparedLight> PrepareLights(const Scene& scene, const glm::mat4& toSpace) {
  std::vector<PreparedLight> lights;
  for (const DirectionalLight& l : scene.directionalLights) lights.push_back(Prepare(l, toSpace));
  for (const SpotLight& l : scene.spotLights) lights.push_back(Prepare(l, toSpace));
  return lights;
}

}  // namespace ssgi
