// Small scenes built in code for the pass tests: quads, boxes, a ground plane, sun directions.
#pragma once

#include <optional>

#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/mesh.h"
#include "core/scene.h"
#include "passes/frame_config.h"

namespace ssgi::test {

// A quad o, o + u, o + u + v, o + v, counter-clockwise seen from the side cross(u, v) points to,
// with flat normals and material 0.
void AddQuad(Mesh& mesh, glm::vec3 o, glm::vec3 u, glm::vec3 v);

// An axis-aligned box with outward faces and flat normals.
void AddBox(Mesh& mesh, glm::vec3 lo, glm::vec3 hi);

// The plane y = 0, `half` metres each way from the origin, facing up.
void AddGround(Mesh& mesh, float half);

// A direction travelling down at `fromNormalDeg` from -y, its horizontal part at `azimuthDeg` from +x.
glm::vec3 LightDirection(float fromNormalDeg, float azimuthDeg);

// A directional light travelling along `direction` with the given angular diameter.
DirectionalLight Sun(glm::vec3 direction, float angularDiameterDegrees);

// The world-space position of G-buffer pixel (x, y) seen by `camera` (word 2 depth).
glm::vec3 WorldPosition(const ViewProjection& camera, const GBuffer& gbuffer, int x, int y);

// For a point p on the floor y = 0 seen from `eye`, in front of the box [lo, hi] standing on it:
// where the mirror image of the view ray meets the box's front face z = hi.z, if it does at least
// `margin` metres inside the face's edges (nearer ones are ambiguous pixels). nullopt otherwise,
// and for any p that is not on the floor in front of the box.
std::optional<glm::vec3> MirrorPointOnBoxFront(glm::vec3 eye, glm::vec3 p, glm::vec3 lo, glm::vec3 hi, float margin);

// A scene with the frame size and G-buffer encoding a test renders it at.
struct TestScene : Scene {
  int width = kDefaultImageSide;
  int height = kDefaultImageSide;
  NormalEncoding normalEncoding = NormalEncoding::kOct24;
  glm::vec3 background{0.0f};
};

// An empty scene of the given size with one two-sided default material.
TestScene MakeScene(const CameraDesc& camera, int width, int height);
// A loaded scene to be rendered at the given size.
TestScene Sized(Scene scene, int width, int height);
// The default frame configuration at the scene's size, encoding and background.
FrameConfig ConfigOf(const TestScene& scene);

}  // namespace ssgi::test
