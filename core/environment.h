// The environment: light from infinitely far away, arriving from every direction no geometry
// blocks. It is what the camera sees where no geometry covers a pixel, and it lights every surface,
// as a world colour does in every physically based renderer (docs/design.md §2). A scene file's
// "environment" (docs/user-guide.md "Scene files").
#pragma once

#include <glm/glm.hpp>

namespace ssgi {

enum class EnvironmentKind {
  kConstant,  // the same radiance from every direction
};

struct Environment {
  EnvironmentKind kind = EnvironmentKind::kConstant;
  glm::vec3 radiance{0.0f};  // kConstant: linear RGB radiance, W/(m^2 sr), each component >= 0

  // The radiance arriving along -direction, that is seen looking along `direction` (world space,
  // unit length).
  glm::vec3 Radiance(const glm::vec3& /*direction*/) const { return radiance; }
  bool IsBlack() const { return radiance == glm::vec3(0.0f); }
};

}  // namespace ssgi
