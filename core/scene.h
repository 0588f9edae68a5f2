// Scenes: the JSON scene format (README "Scene files") and bare OBJ files, loaded into one
// world-space mesh with its materials, textures, camera, lights and render settings.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/material.h"
#include "core/mesh.h"
#include "core/texture.h"

namespace ssgi {

struct DirectionalLight {
  glm::vec3 direction{0.0f, -1.0f, 0.0f};  // unit; the direction the light travels (towards the scene)
  glm::vec3 irradiance{3.0f};              // linear RGB, W/m^2 on a surface facing the light
  float angularDiameterDegrees = 0.53f;    // the sun's; drives penumbra width
  bool castShadows = true;
};

struct SpotLight {
  glm::vec3 position{0.0f, 3.0f, 0.0f};
  glm::vec3 direction{0.0f, -1.0f, 0.0f};  // unit; cone axis
  float innerConeDegrees = 20.0f;          // half-angle of full intensity
  float outerConeDegrees = 30.0f;          // half-angle where intensity reaches 0; >= inner
  float radius = 0.05f;                    // metres; emitter size, drives penumbra width
  glm::vec3 intensity{10.0f};              // linear RGB, W/sr on the axis
  bool castShadows = true;
};

enum class NormalEncoding { kXyz8, kOct24 };

// "auto": run the effect when the scene calls for it (DESIGN.md §9); on / off force it.
enum class EffectMode { kAuto, kOn, kOff };

enum class Tonemap { kAces, kClamp };

struct RenderSettings {
  int width = 1024;
  int height = 1024;
  float exposureEv = 0.0f;              // image scaled by 2^exposureEv before the tonemap
  Tonemap tonemap = Tonemap::kAces;
  glm::vec3 background{0.0f};           // linear radiance of pixels no geometry covers
  NormalEncoding normalEncoding = NormalEncoding::kOct24;
  EffectMode shadows = EffectMode::kAuto;
  EffectMode reflections = EffectMode::kAuto;
};

inline constexpr int kMaxImageSize = 16384;

struct Scene {
  std::filesystem::path source;  // the file it was loaded from
  CameraDesc camera;
  std::vector<DirectionalLight> directionalLights;
  std::vector<SpotLight> spotLights;
  Mesh mesh;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  RenderSettings settings;
  size_t reorientedTriangles = 0;  // triangles the OBJ loader turned to match their neighbours' winding
};

// Loads a scene: a .json scene file (README "Scene files") or a bare .obj file, which gets a camera
// framing its bounds and the default light. Throws InputError (file, line where known, problem) for
// malformed JSON/OBJ/MTL, unknown or ill-typed keys, missing files or textures, non-finite vertices,
// out-of-range values and image sizes outside [1, kMaxImageSize].
Scene LoadScene(const std::filesystem::path& file);

// Parses an image size "WIDTHxHEIGHT" (or "WxH" with a capital X), each side in [1, kMaxImageSize].
// Throws InputError naming --size and the text otherwise.
void ParseImageSize(const std::string& text, int& width, int& height);

// The camera and light `ssgi render model.obj` uses: looks at the bounding sphere of `mesh` from the
// front-right and above, with a directional light from the upper left.
CameraDesc FrameMesh(const Mesh& mesh, int width, int height);
DirectionalLight DefaultLight();

}  // namespace ssgi
