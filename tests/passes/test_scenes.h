// Small scenes built in code for the pass tests: quads, boxes, a ground plane, sun directions.
#pragma once

#include <algorithm>
#include <cstring>
#include <functional>
#include <optional>
#include <random>
#include <vector>

#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/mesh.h"
#include "core/procedural_mesh.h"
#include "core/plane.h"
#include "core/scene.h"
#include "passes/frame/frame.h"
#include "passes/frame/config.h"

namespace ssgi::test {

// Quads and boxes (core/procedural_mesh.h), material 0 unless given.
using ::ssgi::AddBox;
using ::ssgi::AddQuad;

// The plane y = 0, `half` metres each way from the origin, facing up.
void AddGround(Mesh& mesh, float half);

// A direction travelling down at `fromNormalDeg` from -y, its horizontal part at `azimuthDeg` from +x.
glm::vec3 LightDirection(float fromNormalDeg, float azimuthDeg);

// A directional light travelling along `direction` with the given angular diameter.
DirectionalLight Sun(glm::vec3 direction, float angularDiameterDegrees);

// A spot light at `position` pointing along `direction` (normalised here), other settings default.
SpotLight Spot(glm::vec3 position, glm::vec3 direction, float outerConeDegrees, float radius);

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

// A perspective and an orthographic view of width x height looking down on the origin: where the SIMD
// twins' tests place their random G-buffer rows.
std::vector<ViewProjection> TwinTestViews(int width, int height);

// G-buffer words 0 to 2 of one row of `width` random pixels: any words 0 and 1 (every bit pattern is
// a valid code), a depth in word 2 or, for about one pixel in four, background.
struct RandomGBufferRow {
  std::vector<uint32_t> word[3];  // words 0-2
  RandomGBufferRow(size_t width, std::mt19937& rng);
};

// data/default.json and its render block, with the diffuse bounce on (the scene's own frame leaves it
// to the interreflection volume): real buffers for tests that compare two ways of running a pass.
struct DefaultScene {
  Scene scene;
  FrameConfig config;
  // A frame of it at width x height.
  Frame Render(int width, int height) const;
};
DefaultScene LoadDefaultScene();

// Calls check(frame) for data/default.json rendered at its own size, 1024x1024, and at 1023x769,
// 67x45 and 1x1: frames on which a pass's SIMD kernels must give its scalar kernels' bytes.
void ForEachDefaultSceneFrame(const std::function<void(const Frame&)>& check);

// Whether two planes of one size hold the same bytes in every pixel (padding aside).
template <class T>
bool SameBytes(const Plane<T>& a, const Plane<T>& b) {
  if (a.xsize() != b.xsize() || a.ysize() != b.ysize()) return false;
  for (size_t y = 0; y < a.ysize(); ++y)
    if (std::memcmp(a.ConstRow(y), b.ConstRow(y), a.xsize() * sizeof(T)) != 0) return false;
  return true;
}

// The same for each of three planes.
template <class T>
bool SameBytes(const Plane3<T>& a, const Plane3<T>& b) {
  return SameBytes(a.c[0], b.c[0]) && SameBytes(a.c[1], b.c[1]) && SameBytes(a.c[2], b.c[2]);
}

// `scene` with its camera high above it, looking straight up: a frame of it sees only the
// environment.
inline Scene FacingTheSky(Scene scene) {
  scene.camera.position = {0.0f, 50.0f, 0.0f};
  scene.camera.target = {0.0f, 100.0f, 0.0f};
  scene.camera.up = {0.0f, 0.0f, 1.0f};
  return scene;
}

// A copy of three planes (planes cannot be copied).
inline Plane3<float> CopyOf(const Plane3<float>& planes) {
  const size_t width = planes.c[0].xsize(), height = planes.c[0].ysize();
  Plane3<float> copy = MakePlane3<float>(width, height, 0.0f);
  for (int c = 0; c < 3; ++c)
    for (size_t y = 0; y < height; ++y) std::copy_n(planes.c[c].ConstRow(y), width, copy.c[c].MutableRow(y));
  return copy;
}

}  // namespace ssgi::test
