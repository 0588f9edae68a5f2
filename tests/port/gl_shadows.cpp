#include "tests/port/gl_shadows.h"

#include <bit>
#include <vector>

#include "core/closed_surfaces.h"
#include "core/lighting.h"
#include "core/raster/scene_raster_input.h"

namespace ssgi::port {
namespace {

// The first shadow-casting light, in world space.
PreparedLight ShadowedLight(const Scene& scene, size_t& index) {
  index = ShadowCastingLights(scene).front();
  return PrepareLights(scene, glm::mat4(1.0f))[index];
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
// through the world): light_bounds.comp's groups, folded; their count goes to `count`.
LightViewBounds ReceiverBounds(const ShadowInputs& in, const glm::mat4& rotation, size_t& count) {
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
  LightViewBounds bounds;
  count = 0;
  for (size_t group = 0; group < words.size() / 7; ++group) {
    const auto at = [&](size_t k) { return std::bit_cast<float>(words[7 * group + k]); };
    count += size_t(at(0));
    bounds.Add(LightViewBounds{{at(1), at(2), at(3)}, {at(4), at(5), at(6)}});
  }
  return bounds;
}

}  // namespace

ShadowMapResult RunPortShadowMap(const ShadowInputs& in, const ShadowMapParams& params, bool rasterize) {
  size_t index = 0;
  const PreparedLight light = ShadowedLight(in.scene, index);
  // One sweep counts the receivers and bounds them in the directional light's rotation; the window
  // is then the oracle's fit of those bounds.
  size_t receiverCount = 0;
  const LightViewBounds receivers = ReceiverBounds(in, ShadowFitRotation(light), receiverCount);
  const ViewProjection lightView = FitLightView(in.scene, index, receiverCount, receivers, params);
  if (!rasterize) return {lightView, Buffer(0)};
  const size_t texels = size_t(params.resolution) * size_t(params.resolution);
  if (receiverCount == 0) return {lightView, Buffer(texels, std::vector<float>(texels, 0.0f).data())};
  // Both faces drawn, but the back faces of the closed surfaces the spec culls (found in the mesh on
  // the CPU, as an engine keeps static geometry's); cut-outs alpha tested with the light's rays.
  const ClosedSurfaces closed = FindClosedSurfaces(in.scene.mesh);
  const std::vector<uint8_t> culled = CulledClosedSurfaces(in.scene, closed, lightView);
  std::vector<uint32_t> closedCulled(closed.surface.size(), 0u);
  for (size_t t = 0; t < closedCulled.size(); ++t)
    closedCulled[t] = closed.surface[t] != ClosedSurfaces::kOpen && culled[closed.surface[t]];
  VisibilityTargets map = RunVisibilityPass(in.sceneBuffers, lightView, false, RasterKind::kDepthOnly, 8, closedCulled);
  return {lightView, std::move(map.depthKey)};
}

Buffer RunPortBlockerSearch(const ShadowInputs& in, const ShadowMapParams& params, const ViewProjection& lightView,
                            const Buffer& depthKey) {
  size_t index = 0;
  const PreparedLight light = ShadowedLight(in.scene, index);
  const Program program("blocker_search.comp", {"shadow.glsl"});
  SetCamera(program, in);
  SetCameraToLight(program, lightView.view * glm::inverse(in.camera.view));
  std::vector<float> pattern;
  for (const glm::vec2& tap : BlockerSearchPattern(params.blockerSearchTaps))
    pattern.insert(pattern.end(), {tap.x, tap.y});
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
