// Light sources seen from a shaded point (docs/design.md §5): one evaluation for the screen-space passes
// and the Embree reference. A light is prepared once per frame in the space the caller shades in
// (view space for the passes, world space for the reference), then evaluated per point.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <vector>

#include "core/brdf.h"
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

// A point light is a spot whose cone never cuts: (cos - (-3)) * 1 is at least 2 for any cosine, so
// the cone factor clamps to exactly 1 and every kernel and port of the spot's formula shades it.
inline PreparedLight Prepare(const PointLight& light, const glm::mat4& toSpace) {
  PreparedLight p;
  p.isSpot = true;
  p.position = glm::vec3(toSpace * glm::vec4(light.position, 1.0f));
  p.direction = glm::vec3(0.0f, 0.0f, -1.0f);
  p.power = light.intensity;
  p.radius = light.radius;
  p.cosOuter = -3.0f;
  p.coneScale = 1.0f;
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

// The direction a disk light's specular term is evaluated toward: a representative point (Karis
// 2013, "Real Shading in Unreal Engine 4", area lights). r is the unit mirror direction of the view,
// l the unit direction to the disk's centre, `radius` the radius of a disk facing the point at
// distance 1 along l (DiskLightBrdfCosine passes one a little under the light's own, see there).
// Where r passes through the disk, r itself. Outside, the point on the way from the centre to r
// whose distance from r, measured in the disk's plane, is sqrt(T^2 - radius^2) for r's distance T
// from the centre: that map takes the plane less the disk onto the whole plane preserving area, so a
// lobe evaluated there keeps its energy, and far from the disk it tends to the point light at the
// centre. Karis's closest point (distance T - radius) would move every far tail in by the radius.
// The point's offset from the centre is k s, with s r's offset from l across it and T = |s| / (r.l):
// k = radius^2 / (T (T + sqrt(T^2 - radius^2))), computed as (radius u) / (|s| (|s| + sqrt(|s|^2 -
// u^2))) with u = radius (r.l), which stays finite. l itself when r points away from the light's
// side (r.l <= 0) and for radius 0.
inline glm::vec3 RepresentativeDirection(const glm::vec3& r, const glm::vec3& l, float radius) {
  const float rDotL = glm::dot(r, l);
  if (!(rDotL > 0.0f) || !(radius > 0.0f)) return l;
  const glm::vec3 s = r - l * rDotL;
  const float sLength = std::sqrt(glm::dot(s, s));
  const float u = radius * rDotL;
  if (sLength <= u) return r;
  // sLength > u >= 0 here, so sLength^2 - u^2 >= 0 in float too.
  const float k = (radius * u) / (sLength * (sLength + std::sqrt(sLength * sLength - u * u)));
  return glm::normalize(l + s * k);
}

// BRDF times n.l over a disk light of angular radius atan(tanAngularRadius) around the unit direction
// l, per unit of the irradiance the disk gives a surface facing it, so that times the light's
// irradiance it is the reflected radiance (docs/pipeline.md §Direct light; the Embree reference
// samples the disk instead). 0 where n.l <= 0 or n.v <= 0, as BrdfCosine.
//
// Lambert: albedo ((1 - metallic) / pi) n.l, the centre's, which is exact for a disk above the
// horizon (n.l' averaged over the disk and normalised to its irradiance is n.l).
//
// GGX: BrdfCosine's specular term F D V n.l (V n.l as SmithGgxCorrelatedVisibilityCosine) with the
// material's alpha a (at least kMinGgxAlpha), evaluated toward a representative direction with D
// limited to a peak. In the half vector's slope space, where
// D(m) = a^2 / (pi (a^2 + |m|^2)^2), the light near the highlight is a disk of radius
// rho = t / (2 sqrt(n.v)) (the half vector's solid angle is the light's over 4 v.h, and v.h = n.v on
// the highlight), and the true highlight is D averaged over that disk. Its peak, 1 / (pi (a^2 +
// rho^2)), is the peak of GGX with alpha a' = sqrt(a^2 + rho^2): D is limited to 1 / (pi a'^2).
// The representative direction remaps a disk of slope radius a' - a = rho^2 / (a + a') (a radius of
// t rho / (a + a') in RepresentativeDirection's plane): the one whose flat top at that limit holds
// exactly the energy the limit takes off the remapped lobe, so the highlight keeps the lobe's
// energy whatever the light's size and the roughness (tests/passes/direct_light_test.cpp integrates
// it). A near-mirror thus reflects the disk at the disk's radiance, a lobe much wider than the disk
// keeps its own peak, and away from the highlight the lobe tends to the point light's, as the
// average over the disk does. Widening alpha to a + t / 2 instead (Karis's sphere light) brightens
// those tails by about ((a + t / 2) / a)^2, 39x at roughness 0.05 under a 3 degree sun, and Karis's
// energy normalisation (a / (a + t / 2))^2 of a representative point darkens them about as much.
// The specular term is 0 where the representative direction is below the surface; a' is at most 1
// (lights near the size of the sky, grazing views).
inline glm::vec3 DiskLightBrdfCosine(const SurfaceMaterial& m, float alpha, const glm::vec3& n, const glm::vec3& v,
                                     const glm::vec3& l, float tanAngularRadius) {
  const float nDotL = glm::dot(n, l);
  const float nDotV = glm::dot(n, v);
  if (!(nDotL > 0.0f) || !(nDotV > 0.0f)) return glm::vec3(0.0f);
  const glm::vec3 diffuse = m.albedo * ((1.0f - m.metallic) / kPi);
  const float a = std::max(alpha, kMinGgxAlpha);
  const float slopeRadius = (0.5f * tanAngularRadius) / std::sqrt(nDotV);
  const float peakAlpha = std::min(1.0f, std::sqrt(a * a + slopeRadius * slopeRadius));
  const glm::vec3 r = n * (2.0f * nDotV) - v;  // reflect(-v, n)
  const glm::vec3 toDisk = RepresentativeDirection(r, l, (tanAngularRadius * slopeRadius) / (a + peakAlpha));
  const float nDotDisk = glm::dot(n, toDisk);
  glm::vec3 specular(0.0f);
  if (nDotDisk > 0.0f) {
    glm::vec3 h = v + toDisk;
    const float hLength = glm::length(h);
    h = hLength > 0.0f ? h / hLength : n;
    const float nDotH = std::clamp(glm::dot(n, h), 0.0f, 1.0f);
    const float vDotH = std::clamp(glm::dot(v, h), 0.0f, 1.0f);
    const float d = std::min(GgxDistribution(nDotH, a), 1.0f / (kPi * (peakAlpha * peakAlpha)));
    specular = SchlickFresnel(vDotH, SpecularF0(m)) * (d * SmithGgxCorrelatedVisibilityCosine(nDotV, nDotDisk, a));
  }
  return diffuse * nDotL + specular;
}

// Every light of a scene, prepared in one space; directional lights first, then spots, then point
// lights, each in scene order (light indices in per-light buffers follow this order).
inline std::vector<PreparedLight> PrepareLights(const Scene& scene, const glm::mat4& toSpace) {
  std::vector<PreparedLight> lights;
  for (const DirectionalLight& l : scene.directionalLights) lights.push_back(Prepare(l, toSpace));
  for (const SpotLight& l : scene.spotLights) lights.push_back(Prepare(l, toSpace));
  for (const PointLight& l : scene.pointLights) lights.push_back(Prepare(l, toSpace));
  return lights;
}

}  // namespace ssgi
