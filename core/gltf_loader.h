// glTF 2.0 loading (.gltf, .glb), internal to core (the scene loader bakes its result into world
// space, as it does an OBJ's). tinygltf parses the JSON, the buffers and the images (stb_image);
// this layer adds the checks it leaves out (accessor bounds, index ranges, non-finite values,
// required extensions, node cycles) and turns the model into ssgi's mesh, materials, textures,
// lights and camera. docs/user-guide.md "glTF files" lists what is supported and how each feature
// maps; every refusal is one InputError naming the file, every approximation one warning.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/material.h"
#include "core/mesh.h"
#include "core/scene.h"
#include "core/texture.h"

namespace ssgi {

// lm/W: KHR_lights_punctual's lux (directional) and candela (spot, point) become W/m^2 and W/sr by
// dividing by the luminous efficacy of 555 nm light, the photometric definition.
inline constexpr float kLumensPerWatt = 683.0f;

struct GltfCamera {
  CameraDesc desc;        // in the model's space (node transforms applied)
  float aspectRatio = 0;  // width / height the file asks for; 0 when it leaves it to the renderer
};

struct GltfModel {
  // Model space: every node's mesh instance with its node's world transform. mesh.materials index
  // `materials`, whose texture indices index `textures`. tangents are filled when a material has a
  // normal texture, colors when a primitive has COLOR_0. At least one triangle.
  Mesh mesh;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<GltfCamera> cameras;  // the scene's camera instances, in node order
  std::vector<DirectionalLight> directionalLights;
  std::vector<SpotLight> spotLights;
  std::vector<PointLight> pointLights;
  std::vector<std::string> warnings;  // one line each, naming the file
};

// Loads `file` (.gltf or .glb by its extension). Throws InputError naming the file for malformed JSON,
// missing buffers or images, out-of-range accessors or indices, unsupported required extensions
// (Draco among them), point and line primitives, node cycles, non-finite values and a scene without
// triangles.
GltfModel LoadGltfModel(const std::filesystem::path& file);

// MikkTSpace-compatible tangents (Mikkelsen 2008, "Simulation of wrinkled surfaces revisited") for
// `mesh`'s positions, normals and uvs, into mesh.tangents: per triangle corner the UV gradient's
// tangent and bitangent, projected into the plane of the corner's normal, weighted by the corner's
// angle and summed over the corners that share position, normal, UV and the UV triangle's
// orientation; the sign is that orientation's. A vertex whose corners disagree in orientation is
// split (appended; the indices of the minority's triangles move to the copy). Degenerate UV
// triangles contribute nothing; a vertex left without a tangent gets any unit vector orthogonal to
// its normal, with sign +1.
void GenerateTangents(Mesh& mesh);

}  // namespace ssgi
