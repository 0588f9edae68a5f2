#include "core/camera.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "core/check.h"

namespace ssgi {

ViewProjection MakePerspective(const CameraDesc& camera, int width, int height) {
  SSGI_CHECK_GT(width, 0);
  SSGI_CHECK_GT(height, 0);
  SSGI_CHECK_GT(camera.nearPlane, 0.0f);
  ViewProjection vp;
  vp.width = width;
  vp.height = height;
  vp.nearPlane = camera.nearPlane;
  vp.view = glm::lookAt(camera.position, camera.target, camera.up);
  const float tanHalfY = std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
  vp.halfY = tanHalfY;
  vp.halfX = tanHalfY * float(width) / float(height);
  // Reversed-Z infinite perspective: clip = (x / halfX, y / halfY, near, -z).
  glm::mat4 p(0.0f);
  p[0][0] = 1.0f / vp.halfX;
  p[1][1] = 1.0f / vp.halfY;
  p[3][2] = camera.nearPlane;
  p[2][3] = -1.0f;
  vp.projection = p;
  vp.viewProjection = vp.projection * vp.view;
  return vp;
}

glm::vec3 UpHint(const glm::vec3& forward) {
  const glm::vec3 a = glm::abs(forward);
  if (a.x <= a.y && a.x <= a.z) return {1.0f, 0.0f, 0.0f};
  if (a.y <= a.z) return {0.0f, 1.0f, 0.0f};
  return {0.0f, 0.0f, 1.0f};
}

ViewProjection MakeOrthographic(const glm::vec3& eye, const glm::vec3& forward, const glm::vec3& up,
                                float halfX, float halfY, float nearPlane, float farPlane, int width,
                                int height) {
  SSGI_CHECK_GT(farPlane, nearPlane);
  ViewProjection vp;
  vp.width = width;
  vp.height = height;
  vp.orthographic = true;
  vp.nearPlane = nearPlane;
  vp.farPlane = farPlane;
  vp.halfX = halfX;
  vp.halfY = halfY;
  vp.view = glm::lookAt(eye, eye + forward, up);
  // Reversed-Z orthographic: z_ndc = (far + z_view) / (far - near), 1 at near, 0 at far.
  glm::mat4 p(0.0f);
  p[0][0] = 1.0f / halfX;
  p[1][1] = 1.0f / halfY;
  p[2][2] = 1.0f / (farPlane - nearPlane);
  p[3][2] = farPlane / (farPlane - nearPlane);
  p[3][3] = 1.0f;
  vp.projection = p;
  vp.viewProjection = vp.projection * vp.view;
  return vp;
}

PixelRayTables MakePixelRayTables(const ViewProjection& view, size_t columns, size_t rows) {
  PixelRayTables rays{std::vector<float>(columns), std::vector<float>(rows)};
  for (size_t x = 0; x < columns; ++x) rays.x[x] = view.PixelRay(float(x) + 0.5f, 0.5f).direction.x;
  for (size_t y = 0; y < rows; ++y) rays.y[y] = view.PixelRay(0.5f, float(y) + 0.5f).direction.y;
  return rays;
}

}  // namespace ssgi
