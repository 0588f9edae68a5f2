// Metallic-roughness materials (docs/design.md §2), as carried by OBJ/MTL and scene overrides.
#pragma once

#include <cstdint>
#include <string>

#include <glm/glm.hpp>

namespace ssgi {

inline constexpr int32_t kNoTexture = -1;

struct Material {
  std::string name;
  glm::vec3 baseColor{0.8f};  // linear; multiplies baseColorTexture
  float metallic = 0.0f;      // [0, 1]; multiplies metallicTexture
  float roughness = 0.5f;     // perceptual roughness r in [0, 1], GGX alpha = r^2; multiplies roughnessTexture
  int32_t baseColorTexture = kNoTexture;  // indices into Scene::textures
  int32_t metallicTexture = kNoTexture;
  int32_t roughnessTexture = kNoTexture;
  int32_t alphaTexture = kNoTexture;      // map_d: cut-out where alpha < alphaCutoff
  float alphaCutoff = 0.5f;
  bool twoSided = false;  // false: back faces are culled
  // Tangent-space normal map (glTF's normalTexture, linear RGB = (x, y, z) * 0.5 + 0.5); needs the
  // mesh's tangents. normalScale scales its x and y (docs/pipeline.md §G-buffer, "Normal mapping").
  int32_t normalTexture = kNoTexture;
  float normalScale = 1.0f;
  bool vertexColors = false;  // the mesh's colors multiply baseColor
};

}  // namespace ssgi
