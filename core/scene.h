// Scenes: the JSON scene format (docs/user-guide.md "Scene files") and bare OBJ files, loaded into one
// world-space mesh with its materials, textures, camera, lights and render settings.
#pragma once

#include <filesystem>
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/environment.h"
#include "core/material.h"
#include "core/mesh.h"
#include "core/render_modes.h"
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

// A point light: unshadowed in the frame and in the reference, since a shadow needs a cube map the
// design does not have (word 3 and the shadow map hold one light's view; docs/pipeline.md §Direct
// light). The scene loader warns once per scene that has one.
struct PointLight {
  glm::vec3 position{0.0f, 3.0f, 0.0f};
  float radius = 0.05f;        // metres; emitter size (the specular disk, the distance clamp)
  glm::vec3 intensity{10.0f};  // linear RGB, W/sr in every direction
};

inline constexpr int kMaxImageSize = 16384;
inline constexpr int kDefaultImageSide = 1024;  // width and height of a frame when nothing sets them

struct Scene {
  std::filesystem::path source;  // the file it was loaded from
  CameraDesc camera;
  std::vector<DirectionalLight> directionalLights;
  std::vector<SpotLight> spotLights;
  std::vector<PointLight> pointLights;
  Environment environment;  // black unless the scene file gives one
  Mesh mesh;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  size_t reorientedTriangles = 0;  // triangles the OBJ loader turned to match their neighbours' winding
  // What the loaders accepted but do not render as the file asks (one line each, naming the file);
  // the command line prints them as "ssgi: warning: ...".
  std::vector<std::string> warnings;

  bool HasLights() const { return !directionalLights.empty() || !spotLights.empty() || !pointLights.empty(); }
};

// One value of a scene file's "render" block as written: how the file asks for its frames to be
// rendered. The scene loader does not interpret it; the frame configuration's settings table does
// (passes/frame/config.h), so a setting is declared in one place only.
struct RenderBlockEntry {
  std::string key;   // its path under "render": "width", "effects.shadows"
  std::string json;  // the value, as JSON text
  int line = 0;      // in the scene file
};

struct SceneFile {
  Scene scene;
  std::vector<RenderBlockEntry> render;  // empty for a bare OBJ or a file without a render block
};

// Loads a scene: a .json scene file (docs/user-guide.md "Scene files") or a bare .obj file, which gets a camera
// framing its bounds and the default light. A scene file without a camera is framed for the image
// size its render block names (1024x1024 by default). Throws InputError (file, line where known,
// problem) for malformed JSON/OBJ/MTL, unknown or ill-typed keys outside the render block, missing
// files or textures, non-finite vertices and out-of-range values.
SceneFile LoadSceneFile(const std::filesystem::path& file);
// LoadSceneFile's scene, for callers that render it with a configuration of their own.
Scene LoadScene(const std::filesystem::path& file);

// Parses an image size "WIDTHxHEIGHT" (or "WxH" with a capital X), each side in [1, kMaxImageSize].
// Throws InputError with the problem and the text otherwise (callers say where the text came from).
void ParseImageSize(const std::string& text, int& width, int& height);

// Why a camera cannot be rendered: lookAt needs a target away from the position and an up
// direction that is not parallel to the view direction. `key` is the camera key at fault.
struct CameraProblem {
  std::string key;      // "target" or "up"
  std::string problem;  // "must differ from camera.position"
};
std::optional<CameraProblem> FindCameraProblem(const CameraDesc& camera);

// One view of a views file (docs/user-guide.md "Views files"): a camera, and optionally its own
// image size and the first directional light's direction. A view that cannot render carries why,
// and the other views still render.
struct ViewSpec {
  CameraDesc camera;
  int width = 0, height = 0;                // 0: the scene's configured size
  std::optional<glm::vec3> lightDirection;  // unit, the direction the light travels
  std::string error;                        // "<file>:<line>: <problem>" when the view cannot render
};

// `ssgi render-views`' views: "views", a list of views, or "path", camera keyframes interpolated
// over a number of frames. Throws InputError (file, line, problem) when the file as a whole cannot
// be read: not JSON, neither or both of "views" and "path", an empty list, a malformed path; a
// problem inside one view (a bad camera, size or light direction) is that view's error.
std::vector<ViewSpec> LoadViewsFile(const std::filesystem::path& file);

// The camera and light `ssgi render model.obj` uses: looks at the bounding sphere of `mesh` from the
// front-right and above, with a directional light from the upper left.
CameraDesc FrameMesh(const Mesh& mesh, int width, int height);
DirectionalLight DefaultLight();

}  // namespace ssgi
