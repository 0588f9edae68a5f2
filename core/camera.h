// Cameras and the projection convention every pass shares (docs/design.md §2, docs/pipeline.md §Conventions).
//
// World: right-handed, y up, metres. View space is glm::lookAt's: the camera looks down -z, and the
// view depth of a point is d = -z_view > 0.
// Projection is reversed-Z: the near plane maps to z_ndc = 1. Perspective cameras have an infinite far
// plane, so z_ndc = near / d and the depth key stored by the rasterizer falls towards 0 with distance.
// Orthographic cameras (shadow maps) map [near, far] linearly to [1, 0].
// Pixel (x, y) has its origin top-left and its centre at (x + 0.5, y + 0.5).
#pragma once

#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

namespace ssgi {

struct CameraDesc {
  glm::vec3 position{0.0f, 0.0f, 5.0f};
  glm::vec3 target{0.0f, 0.0f, 0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fovYDegrees = 45.0f;  // full vertical field of view
  float nearPlane = 0.05f;    // metres, > 0
};

// Everything a pass needs to map between pixels, view space and clip space for one image size.
struct ViewProjection {
  int width = 1;
  int height = 1;
  bool orthographic = false;
  float nearPlane = 0.05f;
  float farPlane = 0.0f;      // orthographic only; perspective is infinite
  glm::mat4 view{1.0f};       // world -> view
  glm::mat4 projection{1.0f}; // view -> clip (reversed Z)
  glm::mat4 viewProjection{1.0f};
  // Perspective: view-space direction through a pixel is (ndcX * tanHalfX, ndcY * tanHalfY, -1).
  // Orthographic: the half extents of the view volume in metres.
  float halfX = 1.0f;
  float halfY = 1.0f;

  // The view-space ray through image position (px, py); pixel centres are at +0.5. The direction
  // has z = -1 (not unit length), so the point at view depth d is origin + d * direction.
  struct Ray {
    glm::vec3 origin;
    glm::vec3 direction;
  };
  Ray PixelRay(float px, float py) const {
    const float sx = (2.0f * px / float(width) - 1.0f) * halfX;
    const float sy = (1.0f - 2.0f * py / float(height)) * halfY;
    if (orthographic) return {{sx, sy, 0.0f}, {0.0f, 0.0f, -1.0f}};
    return {{0.0f, 0.0f, 0.0f}, {sx, sy, -1.0f}};
  }
  // View depth from the reversed-Z depth key the rasterizer stores (perspective: key = near / d).
  float DepthFromKey(float key) const {
    return orthographic ? nearPlane + (1.0f - key) * (farPlane - nearPlane) : nearPlane / key;
  }
};

ViewProjection MakePerspective(const CameraDesc& camera, int width, int height);

// The centre rays of a perspective view's pixels as two tables, for kernels that would otherwise
// compute them per pixel: PixelRay(x + 0.5, y + 0.5).direction's x for each column x < columns (it
// depends on the column only) and its y for each row y < rows; its z is -1.
struct PixelRayTables {
  std::vector<float> x, y;
};
PixelRayTables MakePixelRayTables(const ViewProjection& view, size_t columns, size_t rows);

// A world axis far from `forward` (the one with its smallest component), so lookAt along `forward`
// is well defined.
glm::vec3 UpHint(const glm::vec3& forward);

// Orthographic view looking along `forward` from `eye`; halfX/halfY in metres, near/far along forward.
ViewProjection MakeOrthographic(const glm::vec3& eye, const glm::vec3& forward, const glm::vec3& up,
                                float halfX, float halfY, float nearPlane, float farPlane, int width,
                                int height);

}  // namespace ssgi
