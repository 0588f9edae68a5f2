#include "passes/gbuffer.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/check.h"
#include "core/color.h"
#include "core/parallel.h"
#include "core/raster/scene_raster_input.h"
#include "core/stopwatch.h"

namespace ssgi {

namespace {

// The material part of a pixel's words: 0 (albedo, metallic) and 1 (normal, roughness) of a pixel of
// `triangle` at surface point `s` with the unit shading normal `normal`: the material's constants
// times its textures' samples, the roughness widened by the normal's `variance` over the pixel.
void ResolveMaterial(const GBufferResolveContext& context, uint32_t triangle, const SurfacePoint& s,
                     const glm::vec3& normal, float variance, uint32_t& word0, uint32_t& word1) {
  const Scene& scene = context.scene;
  const uint32_t materialIndex = scene.mesh.materials[triangle];
  const Material& material = scene.materials[materialIndex];
  if (material.baseColorTexture == kNoTexture && material.metallicTexture == kNoTexture && !material.vertexColors) {
    word0 = context.constantWord0[materialIndex];
  } else {
    glm::vec3 albedo = material.baseColor;
    float metallic = material.metallic;
    if (material.vertexColors)
      albedo *= InterpolatedColor(scene.mesh, &scene.mesh.indices[3 * size_t(triangle)], s.weights);
    if (material.baseColorTexture != kNoTexture)
      albedo *= glm::vec3(SampleTexture(scene.textures[material.baseColorTexture], s.uv, s.uvFootprint));
    if (material.metallicTexture != kNoTexture)
      metallic *= SampleTexture(scene.textures[material.metallicTexture], s.uv, s.uvFootprint).x;
    word0 = PackAlbedoMetallic(albedo, metallic);
  }
  const float kappa = context.specularAaKappa;
  if (material.roughnessTexture == kNoTexture && !(std::min(variance, kappa) > 0.0f)) {
    word1 = EncodeNormal(normal, context.normalEncoding) | context.constantRoughnessBits[materialIndex];
  } else {
    float roughness = material.roughness;
    if (material.roughnessTexture != kNoTexture)
      roughness *= SampleTexture(scene.textures[material.roughnessTexture], s.uv, s.uvFootprint).x;
    word1 = PackNormalRoughness(normal, WidenedRoughness(roughness, variance, kappa), context.normalEncoding);
  }
}

}  // namespace

float NormalVariance(const glm::vec3& m, const glm::vec3& stepX, const glm::vec3& stepY) {
  const float lengthSquared = glm::dot(m, m);
  const glm::vec3 acrossX = stepX - m * (glm::dot(m, stepX) / lengthSquared);
  const glm::vec3 acrossY = stepY - m * (glm::dot(m, stepY) / lengthSquared);
  return (glm::dot(acrossX, acrossX) + glm::dot(acrossY, acrossY)) / lengthSquared * kSpecularAaKernelVariance;
}

float ToksvigVariance(float texelLength) {
  const float length = std::min(texelLength + kNormalTexelLengthTolerance, 1.0f);
  return 2.0f * ((1.0f - length) / length);
}

float WidenedRoughness(float roughness, float variance, float kappa) {
  const float added = std::min(variance, kappa);
  if (!(added > 0.0f)) return roughness;
  const float alpha = roughness * roughness;
  return std::sqrt(std::sqrt(std::min(alpha * alpha + added, 1.0f)));
}

void GBufferResolvePixelScalar(const GBufferResolveContext& context, uint32_t triangle, float depthKey, int x, int y,
                               uint32_t& word0, uint32_t& word1, uint32_t& word2) {
  const Scene& scene = context.scene;
  const SurfaceResolver& resolver = context.resolver;
  const uint32_t materialIndex = scene.mesh.materials[triangle];
  const bool specularAa = context.specularAaKappa > 0.0f;
  const SurfacePoint s = resolver.At(triangle, x, y, context.textured[materialIndex] != 0 || specularAa);
  const uint32_t* idx = &scene.mesh.indices[3 * size_t(triangle)];
  const std::vector<glm::vec3>& normals = scene.mesh.normals;
  glm::vec3 interpolated =
      normals[idx[0]] * s.weights.x + normals[idx[1]] * s.weights.y + normals[idx[2]] * s.weights.z;
  float variance = 0.0f;
  if (specularAa) {
    const glm::vec3 edge1 = normals[idx[1]] - normals[idx[0]], edge2 = normals[idx[2]] - normals[idx[0]];
    variance = NormalVariance(interpolated, edge1 * s.baryStepX.x + edge2 * s.baryStepX.y,
                              edge1 * s.baryStepY.x + edge2 * s.baryStepY.y);
  }
  const Material& material = scene.materials[materialIndex];
  if (material.normalTexture != kNoTexture) {
    const MappedNormal mapped = NormalMapped(scene, material, idx, s.weights, interpolated, s.uv, s.uvFootprint);
    interpolated = mapped.normal;
    if (specularAa) variance = variance + ToksvigVariance(mapped.texelLength);
  }
  glm::vec3 normal = context.normalToView * interpolated;
  const float length = glm::length(normal);
  const glm::vec3& p0 = resolver.ViewPosition(idx[0]);
  const glm::vec3 faceNormal = glm::cross(resolver.ViewPosition(idx[1]) - p0, resolver.ViewPosition(idx[2]) - p0);
  normal = length > 0.0f && std::isfinite(length) ? normal / length : glm::normalize(faceNormal);
  // A two-sided surface seen from behind shades with the side that faces the camera.
  const glm::vec3 toPoint = context.view.PixelRay(float(x) + 0.5f, float(y) + 0.5f).direction;
  if (glm::dot(faceNormal, toPoint) > 0.0f) normal = -normal;
  ResolveMaterial(context, triangle, s, normal, variance, word0, word1);
  word2 = PackDepth(context.view.DepthFromKey(depthKey));
}

size_t GBufferResolveRowScalar(const GBufferResolveContext& context, const uint32_t* triangles,
                               const float* depthKeys, int y, int width, uint32_t* word0, uint32_t* word1,
                               uint32_t* word2, uint32_t* word3) {
  std::fill_n(word3, width, kShadowLit);
  size_t covered = 0;
  for (int x = 0; x < width; ++x) {
    if (triangles[x] == kNoTriangle) {
      word0[x] = 0u;
      word1[x] = 0u;
      word2[x] = PackDepth(kBackgroundDepth);
      continue;
    }
    ++covered;
    GBufferResolvePixelScalar(context, triangles[x], depthKeys[x], x, y, word0[x], word1[x], word2[x]);
  }
  return covered;
}

GBufferStats RunGBuffer(const GBufferInputs& in, const GBufferParams& params, GBufferOutputs& out,
                        KernelPath kernels) {
  const Scene& scene = in.scene;
  const ViewProjection& view = in.view;
  SSGI_CHECK(!view.orthographic);
  for (const Material& material : scene.materials) {
    SSGI_CHECK(material.normalTexture == kNoTexture || scene.mesh.tangents.size() == scene.mesh.positions.size());
    SSGI_CHECK(!material.vertexColors || scene.mesh.colors.size() == scene.mesh.positions.size());
  }
  GBufferStats stats;

  Stopwatch stopwatch;
  const SceneRasterInput raster(scene, view, true);
  // Buffers of the right size from an earlier frame are reused: the raster and the resolve write
  // every pixel of the visibility buffer and of words 0-2, so only word 3 needs resetting.
  const size_t width = size_t(view.width), height = size_t(view.height);
  if (out.visibility.triangle.xsize() != width || out.visibility.triangle.ysize() != height)
    out.visibility = MakeVisibilityBuffer(view.width, view.height, RasterOutput::kVisibility);
  stats.raster = Rasterize(raster.Get(), view, RasterOutput::kVisibility, out.visibility, nullptr, kernels);
  stats.rasterMs = stopwatch.Lap();

  // The resolve writes every pixel of words 0-3. (A frame that freed its buffers after their last
  // readers has no word 3 left: made anew.)
  if (out.gbuffer.width() == view.width && out.gbuffer.height() == view.height &&
      out.gbuffer.word[GBufferWord::kShadowTerm].xsize() == width) {
    out.gbuffer.normalEncoding = params.normalEncoding;
  } else {
    out.gbuffer = MakeGBuffer(view.width, view.height, params.normalEncoding);
  }
  // Word 0 of a material without colour or metallic textures is the same at every pixel, and so is
  // the roughness byte of word 1 without a roughness texture.
  const size_t materials = scene.materials.size();
  std::vector<uint32_t> constantWord0(materials), constantRoughnessBits(materials);
  std::vector<float> constantRoughness(materials);
  std::vector<uint32_t> textured(materials);
  for (size_t m = 0; m < materials; ++m) {
    const Material& material = scene.materials[m];
    constantWord0[m] = PackAlbedoMetallic(material.baseColor, material.metallic);
    constantRoughnessBits[m] = uint32_t(UnormCode8(material.roughness)) << 24;
    constantRoughness[m] = material.roughness;
    textured[m] = material.normalTexture != kNoTexture || material.vertexColors ? kGBufferResolvedPerPixel
                  : material.baseColorTexture != kNoTexture || material.metallicTexture != kNoTexture ||
                          material.roughnessTexture != kNoTexture
                      ? 1u
                      : 0u;
  }
  const PixelRayTables rays = MakePixelRayTables(view, width + kGBufferRayPadding, height + kGBufferRayPadding);
  const GBufferResolveContext context{
      scene,
      view,
      raster.Resolver(),
      constantWord0.data(),
      constantRoughnessBits.data(),
      constantRoughness.data(),
      textured.data(),
      glm::mat3(view.view),  // lookAt is a rotation plus a translation
      params.normalEncoding,
      params.specularAaKappa,
      rays.x.data(),
      rays.y.data(),
  };
  const VisibilityBuffer& visibility = out.visibility;
  std::vector<size_t> coveredPerBand(RowBandCount(height), 0), edgesPerBand(RowBandCount(height), 0);
  if (!params.edgeCoverage) {
    out.edgeCoverage = {};
  } else if (out.edgeCoverage.xsize() != width || out.edgeCoverage.ysize() != height) {
    out.edgeCoverage = MakePlane<uint32_t>(width, height, 0u);
  }
  ParallelForRowBands("gbuffer.resolve", height, [&](size_t band, size_t yBegin, size_t yEnd) {
    // The band's edge coverage first, while its visibility rows are in cache for the resolve too.
    if (params.edgeCoverage)
      edgesPerBand[band] = EdgeCoverageRows(scene, view, visibility, yBegin, yEnd, out.edgeCoverage);
    if (kernels == KernelPath::kSimd) {
      for (size_t y = yBegin; y < yEnd; y += kGBufferResolveRowsPerCall) {
        const int rows = int(std::min(yEnd - y, size_t(kGBufferResolveRowsPerCall)));
        coveredPerBand[band] += GBufferResolveRowsSimd(context, visibility, int(y), rows, out.gbuffer);
      }
      return;
    }
    for (size_t y = yBegin; y < yEnd; ++y) {
      coveredPerBand[band] +=
          GBufferResolveRowScalar(context, visibility.triangle.ConstRow(y), visibility.depthKey.ConstRow(y), int(y),
                                  view.width, out.gbuffer.word[GBufferWord::kAlbedoMetallic].MutableRow(y),
                                  out.gbuffer.word[GBufferWord::kNormalRoughness].MutableRow(y),
                                  out.gbuffer.word[GBufferWord::kDepth].MutableRow(y),
                                  out.gbuffer.word[GBufferWord::kShadowTerm].MutableRow(y));
    }
  });
  for (size_t n : coveredPerBand) stats.coveredPixels += n;
  for (size_t n : edgesPerBand) stats.edgePixels += n;
  stats.resolveMs = stopwatch.Lap();
  return stats;
}

}  // namespace ssgi
