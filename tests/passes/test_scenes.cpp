#include "tests/passes/test_scenes.h"

#include <cmath>

#include "tests/test_support.h"

namespace ssgi::test {

void AddGround(Mesh& mesh, float half) { AddQuad(mesh, {-half, 0, -half}, {0, 0, 2 * half}, {2 * half, 0, 0}); }

glm::vec3 LightDirection(float fromNormalDeg, float azimuthDeg) {
  const float a = glm::radians(fromNormalDeg), b = glm::radians(azimuthDeg);
  return glm::normalize(glm::vec3(std::sin(a) * std::cos(b), -std::cos(a), std::sin(a) * std::sin(b)));
}

DirectionalLight Sun(glm::vec3 direction, float angularDiameterDegrees) {
  DirectionalLight light;
  light.direction = direction;
  light.angularDiameterDegrees = angularDiameterDegrees;
  return light;
}

SpotLight Spot(glm::vec3 position, glm::vec3 direction, float outerConeDegrees, float radius) {
  SpotLight light;
  light.position = position;
  light.direction = glm::normalize(direction);
  light.outerConeDegrees = outerConeDegrees;
  light.radius = radius;
  return light;
}

glm::vec3 WorldPosition(const ViewProjection& camera, const GBuffer& gbuffer, int x, int y) {
  const ViewProjection::Ray ray = camera.PixelRay(float(x) + 0.5f, float(y) + 0.5f);
  const glm::vec3 p = ray.origin + ray.direction * UnpackDepth(gbuffer.word[GBufferWord::kDepth].ConstRow(y)[x]);
  return glm::vec3(glm::inverse(camera.view) * glm::vec4(p, 1.0f));
}

std::optional<glm::vec3> MirrorPointOnBoxFront(glm::vec3 eye, glm::vec3 p, glm::vec3 lo, glm::vec3 hi, float margin) {
  if (!(std::fabs(p.y) < 1e-3f) || !(p.z > hi.z)) return std::nullopt;
  glm::vec3 w = glm::normalize(p - eye);
  w.y = -w.y;  // mirror about y = 0
  if (!(w.z < 0.0f)) return std::nullopt;
  const glm::vec3 q = p + w * ((hi.z - p.z) / w.z);
  if (q.x < lo.x + margin || q.x > hi.x - margin || q.y < lo.y + margin || q.y > hi.y - margin) return std::nullopt;
  return q;
}

TestScene MakeScene(const CameraDesc& camera, int width, int height) {
  TestScene scene;
  scene.camera = camera;
  scene.width = width;
  scene.height = height;
  Material material;
  material.twoSided = true;
  scene.materials.push_back(material);
  return scene;
}

TestScene Sized(Scene scene, int width, int height) {
  TestScene sized;
  static_cast<Scene&>(sized) = std::move(scene);
  sized.width = width;
  sized.height = height;
  return sized;
}

FrameConfig ConfigOf(const TestScene& scene) {
  FrameConfig config;
  config.width = scene.width;
  config.height = scene.height;
  config.normalEncoding = scene.normalEncoding;
  config.environment = ConstantEnvironment(scene.background);
  return config;
}

std::vector<ViewProjection> TwinTestViews(int width, int height) {
  CameraDesc camera;
  camera.position = {0.3f, 2.0f, 4.0f};
  camera.target = {0.0f, 0.3f, 0.0f};
  return {MakePerspective(camera, width, height),
          MakeOrthographic({0.0f, 4.0f, 3.0f}, glm::normalize(glm::vec3(0.0f, -1.0f, -0.8f)), {0.0f, 1.0f, 0.0f},
                           3.0f, 2.0f, 0.1f, 20.0f, width, height)};
}

RandomGBufferRow::RandomGBufferRow(size_t width, std::mt19937& rng) {
  std::uniform_real_distribution<float> depth(0.05f, 30.0f);
  for (size_t x = 0; x < width; ++x) {
    word[GBufferWord::kAlbedoMetallic].push_back(uint32_t(rng()));
    word[GBufferWord::kNormalRoughness].push_back(uint32_t(rng()));
    word[GBufferWord::kDepth].push_back(PackDepth(rng() % 4 == 0 ? kBackgroundDepth : depth(rng)));
  }
}

Frame DefaultScene::Render(int width, int height) const {
  FrameConfig sized = config;
  sized.width = width;
  sized.height = height;
  return RenderFrame(scene, sized);
}

void ForEachDefaultSceneFrame(const std::function<void(const Frame&)>& check) {
  const DefaultScene scene = LoadDefaultScene();
  for (const auto& [width, height] : {std::pair{1024, 1024}, std::pair{1023, 769}, std::pair{67, 45}, std::pair{1, 1}})
    check(scene.Render(width, height));
}

DefaultScene LoadDefaultScene() {
  SceneFile file = LoadSceneFile(SourceDir() / "data" / "default.json");
  FrameConfig config = FrameConfigFromSceneFile(file);
  config.bounce = EffectMode::kOn;
  return {std::move(file.scene), config};
}

}  // namespace ssgi::test
