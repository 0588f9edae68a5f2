#include "tests/port/gl_shadows.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>

#include "core/lighting.h"

namespace ssgi::port {
namespace {

// §Light camera's constants.
constexpr float kMaxSpotFovDegrees = 170.0f;
constexpr float kMinSpotNear = 1e-3f;
constexpr float kMinHalfExtent = 1e-3f;
constexpr float kMinDepthMargin = 1e-3f;
constexpr float kNormalOffsetTexels = 1.0f;
// §Blocker search's golden-angle rotation.
constexpr double kCosGoldenAngle = -0.7373688780783197;
constexpr double kSinGoldenAngle = 0.6754902942615238;

// Light-view bounds, combined as glm's min(a, b) = b < a ? b : a and max(a, b) = a < b ? b : a.
struct Bounds {
  size_t count = 0;
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};
  void Add(const glm::vec3& lower, const glm::vec3& upper) {
    lo = glm::min(lo, lower);
    hi = glm::max(hi, upper);
  }
};

// The first shadow-casting light, in world space.
PreparedLight ShadowedLight(const Scene& scene, size_t& index) {
  index = ShadowCastingLights(scene).front();
  return PrepareLights(scene, glm::mat4(1.0f))[index];
}

// Every mesh vertex in `view` as (x, y, -z), in vertex order: the casters.
Bounds CasterBounds(const Mesh& mesh, const glm::mat4& view) {
  Bounds bounds;
  for (const glm::vec3& position : mesh.positions) {
    const glm::vec3 v(view * glm::vec4(position, 1.0f));
    const glm::vec3 p(v.x, v.y, -v.z);
    bounds.Add(p, p);
  }
  return bounds;
}

void SetCameraToLight(const Program& program, const glm::mat4& cameraToLight) {
  std::vector<float> columns;
  for (int c = 0; c < 4; ++c)
    columns.insert(columns.end(), {cameraToLight[c].x, cameraToLight[c].y, cameraToLight[c].z});
  program.SetArray3("cameraToLight", columns);
}

void SetCamera(const Program& program, const ShadowInputs& in) {
  program.Set("imageSize", in.camera.width, in.camera.height);
  program.Set("tanHalf", in.camera.halfX, in.camera.halfY);
  program.Set("normalEncoding", in.encoding == NormalEncoding::kXyz8 ? 0 : 1);
}

// The receivers (G-buffer pixels with geometry) in the view `rotation` (camera view -> light view
// through the world): light_bounds.comp's groups, folded.
Bounds ReceiverBounds(const ShadowInputs& in, const glm::mat4& rotation) {
  const Program program("light_bounds.comp", {"shadow.glsl"});
  SetCamera(program, in);
  SetCameraToLight(program, rotation * glm::inverse(in.camera.view));
  const int groupsX = (in.camera.width + kGroupSize - 1) / kGroupSize;
  const int groupsY = (in.camera.height + kGroupSize - 1) / kGroupSize;
  const Buffer partials(size_t(groupsX) * size_t(groupsY) * 7);
  in.word2.Bind(0);
  partials.Bind(1);
  program.Dispatch(in.camera.width, in.camera.height);
  const std::vector<uint32_t> words = partials.Download();
  Bounds bounds;
  for (size_t group = 0; group < words.size() / 7; ++group) {
    const auto at = [&](size_t k) { return std::bit_cast<float>(words[7 * group + k]); };
    bounds.count += size_t(at(0));
    bounds.Add({at(1), at(2), at(3)}, {at(4), at(5), at(6)});
  }
  return bounds;
}

// §Light camera, directional: orthographic along the light, its window the receivers' (x, y) box
// padded by the widest search radius and the normal offset, its near plane behind every caster.
ViewProjection FitDirectional(const PreparedLight& light, const Mesh& mesh, const Bounds& receivers,
                              const ShadowMapParams& params) {
  const glm::vec3 up = UpHint(light.direction);
  const glm::mat4 rotation = glm::lookAt(glm::vec3(0.0f), light.direction, up);
  const Bounds casters = CasterBounds(mesh, rotation);
  const float nearDepth = std::min(receivers.lo.z, casters.lo.z);
  const float margin = std::max(kMinDepthMargin, 1e-3f * (receivers.hi.z - nearDepth));
  const float eyeDepth = nearDepth - margin;
  const float farPlane = receivers.hi.z + margin - eyeDepth;
  const float pad = std::min(farPlane, params.maxBlockerDistance) * light.tanAngularRadius;
  const float texelMargin = 1.0f + 2.0f * (kNormalOffsetTexels + 1.0f) / float(params.resolution);
  const float halfX = std::max(kMinHalfExtent, (0.5f * (receivers.hi.x - receivers.lo.x) + pad) * texelMargin);
  const float halfY = std::max(kMinHalfExtent, (0.5f * (receivers.hi.y - receivers.lo.y) + pad) * texelMargin);
  const glm::vec3 centre(0.5f * (receivers.lo.x + receivers.hi.x), 0.5f * (receivers.lo.y + receivers.hi.y), -eyeDepth);
  const glm::vec3 eye = glm::transpose(glm::mat3(rotation)) * centre;
  return MakeOrthographic(eye, light.direction, up, halfX, halfY, 0.0f, farPlane, params.resolution, params.resolution);
}

// §Light camera, spot: perspective along the cone axis over the outer cone, its near plane just
// before the nearest vertex.
ViewProjection FitSpot(const PreparedLight& light, const SpotLight& spot, const Mesh& mesh,
                       const ShadowMapParams& params) {
  CameraDesc desc;
  desc.position = light.position;
  desc.target = light.position + light.direction;
  desc.up = UpHint(light.direction);
  desc.fovYDegrees = std::min(2.0f * spot.outerConeDegrees, kMaxSpotFovDegrees);
  const Bounds casters = CasterBounds(mesh, glm::lookAt(desc.position, desc.target, desc.up));
  desc.nearPlane = mesh.positions.empty() ? kMinSpotNear : std::max(kMinSpotNear, 0.99f * casters.lo.z);
  return MakePerspective(desc, params.resolution, params.resolution);
}

// Vogel's spiral (§Blocker search, "Tap pattern"): tap i at radius sqrt(i / (n - 1)), its angle's
// cosine and sine by repeated rotation in float64, rounded once.
std::vector<float> TapPattern(int taps) {
  std::vector<float> pattern;
  double c = 1.0, s = 0.0;
  for (int i = 0; i < taps; ++i) {
    const double r = taps > 1 ? std::sqrt(double(i) / double(taps - 1)) : 0.0;
    pattern.insert(pattern.end(), {float(r * c), float(r * s)});
    const double nextC = c * kCosGoldenAngle - s * kSinGoldenAngle;
    s = s * kCosGoldenAngle + c * kSinGoldenAngle;
    c = nextC;
  }
  return pattern;
}

}  // namespace

ShadowMapResult RunPortShadowMap(const ShadowInputs& in, const ShadowMapParams& params, bool rasterize) {
  size_t index = 0;
  const PreparedLight light = ShadowedLight(in.scene, index);
  // One sweep counts the receivers and bounds them in the directional light's rotation.
  const glm::mat4 rotation =
      light.isSpot ? glm::mat4(1.0f) : glm::lookAt(glm::vec3(0.0f), light.direction, UpHint(light.direction));
  const Bounds receivers = ReceiverBounds(in, rotation);
  ViewProjection lightView;
  if (light.isSpot) {
    lightView = FitSpot(light, in.scene.spotLights[index - in.scene.directionalLights.size()], in.scene.mesh, params);
  } else if (receivers.count > 0) {
    lightView = FitDirectional(light, in.scene.mesh, receivers, params);
  } else {
    lightView = MakeOrthographic(glm::vec3(0.0f), light.direction, UpHint(light.direction), 1.0f, 1.0f, 0.0f, 1.0f,
                                 params.resolution, params.resolution);
  }
  if (!rasterize) return {lightView, Buffer(0)};
  const size_t texels = size_t(params.resolution) * size_t(params.resolution);
  if (receivers.count == 0) return {lightView, Buffer(texels, std::vector<float>(texels, 0.0f).data())};
  // Both faces drawn; cut-outs alpha tested with the light's rays.
  VisibilityTargets map = RunVisibilityPass(in.sceneBuffers, lightView, false, RasterKind::kDepthOnly);
  return {lightView, std::move(map.depthKey)};
}

Buffer RunPortBlockerSearch(const ShadowInputs& in, const ShadowMapParams& params, const ViewProjection& lightView,
                            const Buffer& depthKey) {
  size_t index = 0;
  const PreparedLight light = ShadowedLight(in.scene, index);
  const Program program("blocker_search.comp", {"shadow.glsl"});
  SetCamera(program, in);
  SetCameraToLight(program, lightView.view * glm::inverse(in.camera.view));
  const std::vector<float> pattern = TapPattern(params.blockerSearchTaps);
  glProgramUniform2fv(program.id(), glGetUniformLocation(program.id(), "pattern"), GLsizei(pattern.size() / 2),
                      pattern.data());
  program.Set("taps", params.blockerSearchTaps);
  const float resolution = float(lightView.width);
  program.Set("lightOrthographic", lightView.orthographic ? 1 : 0);
  program.Set("resolution", lightView.width);
  program.Set("lightNear", lightView.nearPlane);
  program.Set("lightFar", lightView.farPlane);
  program.Set("lightHalf", lightView.halfX, lightView.halfY);
  program.Set("texel", 2.0f * lightView.halfX / resolution, 2.0f * lightView.halfY / resolution);
  program.Set("invTexel", resolution / (2.0f * lightView.halfX), resolution / (2.0f * lightView.halfY));
  program.Set("tanAngularRadius", light.tanAngularRadius);
  program.Set("lightRadius", light.radius);
  program.Set("maxBlockerDistance", params.maxBlockerDistance);
  Buffer word3(size_t(in.camera.width) * size_t(in.camera.height));
  in.word1.Bind(0);
  in.word2.Bind(1);
  depthKey.Bind(2);
  word3.Bind(3);
  program.Dispatch(in.camera.width, in.camera.height);
  return word3;
}

Buffer RunPortShadowFilter(const ShadowInputs& in, const ShadowFilterParams& params, const Buffer& word3) {
  size_t index = 0;
  ShadowedLight(in.scene, index);
  const PreparedLight light = PrepareLights(in.scene, in.camera.view)[index];  // view space
  const Program program("shadow_filter.comp");
  SetCamera(program, in);
  program.Set("filterKind", params.filter == ShadowFilter::kHard ? 0 : params.filter == ShadowFilter::kSspcss ? 1 : 2);
  program.Set("blurTaps", params.taps);
  program.Set("maxRadius", float(params.maxRadiusPixels));
  program.Set("pixelsPerMetreAtUnitDepth", float(in.camera.height) / (2.0f * in.camera.halfY));
  program.Set("lightIsSpot", light.isSpot ? 1 : 0);
  program.Set("lightPosition", light.position.x, light.position.y, light.position.z);
  program.Set("lightRadius", light.radius);
  program.Set("lightTanAngularRadius", light.tanAngularRadius);
  const size_t pixels = size_t(in.camera.width) * size_t(in.camera.height);
  const Buffer setUp(11 * pixels), majorPass(pixels);
  Buffer visibility(pixels);
  in.word1.Bind(0);
  in.word2.Bind(1);
  word3.Bind(2);
  setUp.Bind(3);
  majorPass.Bind(4);
  visibility.Bind(5);
  for (int stage = 0; stage < 3; ++stage) {
    program.Set("stage", stage);
    program.Dispatch(in.camera.width, in.camera.height);
  }
  return visibility;
}

}  // namespace ssgi::port
