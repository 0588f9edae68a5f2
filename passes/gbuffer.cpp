#include "passes/gbuffer.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi {
namespace {

// Barycentrics (b1, b2) of the point where a ray meets the plane of (p0, p1, p2), not limited to
// the triangle (Moller-Trumbore without the bounds test). False when the ray is parallel to it.
bool RayPlaneBarycentrics(const ViewProjection::Ray& ray, const glm::vec3& p0, const glm::vec3& e1,
                          const glm::vec3& e2, glm::vec2& b) {
  const glm::vec3 p = glm::cross(ray.direction, e2);
  const float det = glm::dot(e1, p);
  if (!(std::fabs(det) > 1e-30f)) return false;
  const float invDet = 1.0f / det;
  const glm::vec3 s = ray.origin - p0;
  const glm::vec3 q = glm::cross(s, e1);
  b = {glm::dot(s, p) * invDet, glm::dot(ray.direction, q) * invDet};
  return std::isfinite(b.x) && std::isfinite(b.y);
}

// What the resolve and the alpha test need of one visible point of a triangle.
struct SurfacePoint {
  glm::vec3 weights;  // barycentric weights of the triangle's three vertices, in [0, 1], sum 1
  glm::vec2 uv;
  float uvFootprint;  // larger UV step to the next pixel right or down
};

class SurfaceResolver {
 public:
  SurfaceResolver(const Scene& scene, const ViewProjection& view) : scene_(scene), view_(view) {
    const Mesh& mesh = scene.mesh;
    viewPositions_.resize(mesh.positions.size());
    constexpr size_t kChunk = 16384;
    ParallelFor("gbuffer.view_positions", (mesh.positions.size() + kChunk - 1) / kChunk, [&](size_t c) {
      const size_t end = std::min(mesh.positions.size(), (c + 1) * kChunk);
      for (size_t i = c * kChunk; i < end; ++i)
        viewPositions_[i] = glm::vec3(view.view * glm::vec4(mesh.positions[i], 1.0f));
    });
  }

  const glm::vec3& ViewPosition(uint32_t vertex) const { return viewPositions_[vertex]; }

  SurfacePoint At(uint32_t triangle, int px, int py, bool withFootprint) const {
    const uint32_t* idx = &scene_.mesh.indices[3 * size_t(triangle)];
    const glm::vec3& p0 = viewPositions_[idx[0]];
    const glm::vec3 e1 = viewPositions_[idx[1]] - p0;
    const glm::vec3 e2 = viewPositions_[idx[2]] - p0;
    const float cx = float(px) + 0.5f, cy = float(py) + 0.5f;
    glm::vec2 center(1.0f / 3.0f);
    const bool hit = RayPlaneBarycentrics(view_.PixelRay(cx, cy), p0, e1, e2, center);
    // The pixel centre is inside the snapped triangle, so b leaves [0, 1] only by rounding and
    // snapping; clamping keeps attributes from extrapolating on slivers.
    glm::vec2 b = glm::clamp(center, 0.0f, 1.0f);
    if (b.x + b.y > 1.0f) b /= (b.x + b.y);
    SurfacePoint s;
    s.weights = {1.0f - b.x - b.y, b.x, b.y};
    const std::vector<glm::vec2>& uvs = scene_.mesh.uvs;
    const glm::vec2 uv0 = uvs[idx[0]], du1 = uvs[idx[1]] - uv0, du2 = uvs[idx[2]] - uv0;
    s.uv = uv0 + du1 * b.x + du2 * b.y;
    s.uvFootprint = 0.0f;
    glm::vec2 bx, by;
    // Unclamped here: the footprint is a derivative of the plane's parameterisation.
    if (withFootprint && hit) {
      if (RayPlaneBarycentrics(view_.PixelRay(cx + 1.0f, cy), p0, e1, e2, bx) &&
          RayPlaneBarycentrics(view_.PixelRay(cx, cy + 1.0f), p0, e1, e2, by)) {
        const glm::vec2 ddx = du1 * (bx.x - center.x) + du2 * (bx.y - center.y);
        const glm::vec2 ddy = du1 * (by.x - center.x) + du2 * (by.y - center.y);
        const float footprint = std::max(glm::length(ddx), glm::length(ddy));
        s.uvFootprint = std::isfinite(footprint) ? footprint : 0.0f;
      }
    }
    return s;
  }

 private:
  const Scene& scene_;
  const ViewProjection& view_;
  std::vector<glm::vec3> viewPositions_;
};

float AlphaChannel(const Texture& texture, const glm::vec4& texel) {
  // Grey+alpha and RGBA images carry the mask in alpha; grey and RGB masks in their first channel.
  return texture.sourceChannels == 2 || texture.sourceChannels == 4 ? texel.w : texel.x;
}

struct AlphaTestContext {
  const Scene* scene;
  const SurfaceResolver* resolver;
};

bool PassesAlphaTest(const void* context, uint32_t triangle, int px, int py) {
  const auto& ctx = *static_cast<const AlphaTestContext*>(context);
  const Material& material = ctx.scene->materials[ctx.scene->mesh.materials[triangle]];
  const Texture& texture = ctx.scene->textures[material.alphaTexture];
  const SurfacePoint s = ctx.resolver->At(triangle, px, py, true);
  return AlphaChannel(texture, SampleTexture(texture, s.uv, s.uvFootprint)) >= material.alphaCutoff;
}

}  // namespace

struct SceneRasterInput::Impl {
  Impl(const Scene& scene, const ViewProjection& view) : resolver(scene, view), alphaContext{&scene, &resolver} {}
  SurfaceResolver resolver;
  std::vector<uint8_t> flags;
  AlphaTestContext alphaContext;
};

SceneRasterInput::SceneRasterInput(const Scene& scene, const ViewProjection& view, bool cullBackFaces)
    : impl_(std::make_unique<Impl>(scene, view)) {
  std::vector<uint8_t> materialFlags(scene.materials.size());
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    const Material& material = scene.materials[m];
    materialFlags[m] = uint8_t((cullBackFaces && !material.twoSided ? kTriangleCullBackFace : 0) |
                               (material.alphaTexture != kNoTexture ? kTriangleAlphaTested : 0));
  }
  impl_->flags.resize(scene.mesh.TriangleCount());
  for (size_t t = 0; t < impl_->flags.size(); ++t) impl_->flags[t] = materialFlags[scene.mesh.materials[t]];
  input_.positions = scene.mesh.positions.data();
  input_.vertexCount = scene.mesh.positions.size();
  input_.indices = scene.mesh.indices.data();
  input_.triangleCount = scene.mesh.TriangleCount();
  input_.triangleFlags = impl_->flags.data();
  input_.alphaTest = {&PassesAlphaTest, &impl_->alphaContext};
}

SceneRasterInput::~SceneRasterInput() = default;

GBufferStats RunGBuffer(const GBufferInputs& in, const GBufferParams& params, GBufferOutputs& out) {
  const Scene& scene = in.scene;
  const ViewProjection& view = in.view;
  SSGI_CHECK(!view.orthographic);
  GBufferStats stats;

  Stopwatch stopwatch;
  const SceneRasterInput raster(scene, view, true);
  const SurfaceResolver& resolver = raster.impl_->resolver;
  out.visibility = MakeVisibilityBuffer(view.width, view.height, RasterOutput::kVisibility);
  stats.raster = Rasterize(raster.Get(), view, RasterOutput::kVisibility, out.visibility);
  stats.rasterMs = stopwatch.Lap();

  out.gbuffer = MakeGBuffer(view.width, view.height, params.normalEncoding);
  // Word 0 of a material without colour or metallic textures is the same at every pixel.
  std::vector<uint32_t> constantWord0(scene.materials.size());
  for (size_t m = 0; m < scene.materials.size(); ++m)
    constantWord0[m] = PackAlbedoMetallic(scene.materials[m].baseColor, scene.materials[m].metallic);
  const glm::mat3 normalToView(view.view);  // lookAt is a rotation plus a translation
  std::vector<size_t> coveredPerBand(RowBandCount(size_t(view.height)), 0);
  ParallelForRowBands("gbuffer.resolve", size_t(view.height), [&](size_t band, size_t yBegin, size_t yEnd) {
    for (int y = int(yBegin); y < int(yEnd); ++y) {
      const uint32_t* ids = out.visibility.triangle.ConstRow(y);
      const float* keys = out.visibility.depthKey.ConstRow(y);
      uint32_t* w0 = out.gbuffer.word[0].MutableRow(y);
      uint32_t* w1 = out.gbuffer.word[1].MutableRow(y);
      uint32_t* w2 = out.gbuffer.word[2].MutableRow(y);
      for (int x = 0; x < view.width; ++x) {
        const uint32_t triangle = ids[x];
        if (triangle == kNoTriangle) continue;
        ++coveredPerBand[band];
        const uint32_t materialIndex = scene.mesh.materials[triangle];
        const Material& material = scene.materials[materialIndex];
        const bool textured = material.baseColorTexture != kNoTexture || material.metallicTexture != kNoTexture ||
                              material.roughnessTexture != kNoTexture;
        const SurfacePoint s = resolver.At(triangle, x, y, textured);
        const uint32_t* idx = &scene.mesh.indices[3 * size_t(triangle)];
        const std::vector<glm::vec3>& normals = scene.mesh.normals;
        glm::vec3 normal = normalToView * (normals[idx[0]] * s.weights.x + normals[idx[1]] * s.weights.y +
                                           normals[idx[2]] * s.weights.z);
        const float length = glm::length(normal);
        const glm::vec3& p0 = resolver.ViewPosition(idx[0]);
        const glm::vec3 faceNormal =
            glm::cross(resolver.ViewPosition(idx[1]) - p0, resolver.ViewPosition(idx[2]) - p0);
        normal = length > 0.0f && std::isfinite(length) ? normal / length : glm::normalize(faceNormal);
        // A two-sided surface seen from behind shades with the side that faces the camera.
        const glm::vec3 toPoint = view.PixelRay(float(x) + 0.5f, float(y) + 0.5f).direction;
        if (glm::dot(faceNormal, toPoint) > 0.0f) normal = -normal;

        if (material.baseColorTexture == kNoTexture && material.metallicTexture == kNoTexture) {
          w0[x] = constantWord0[materialIndex];
        } else {
          glm::vec3 albedo = material.baseColor;
          float metallic = material.metallic;
          if (material.baseColorTexture != kNoTexture)
            albedo *= glm::vec3(SampleTexture(scene.textures[material.baseColorTexture], s.uv, s.uvFootprint));
          if (material.metallicTexture != kNoTexture)
            metallic *= SampleTexture(scene.textures[material.metallicTexture], s.uv, s.uvFootprint).x;
          w0[x] = PackAlbedoMetallic(albedo, metallic);
        }
        float roughness = material.roughness;
        if (material.roughnessTexture != kNoTexture)
          roughness *= SampleTexture(scene.textures[material.roughnessTexture], s.uv, s.uvFootprint).x;

        w1[x] = PackNormalRoughness(normal, roughness, params.normalEncoding);
        w2[x] = PackDepth(view.DepthFromKey(keys[x]));
      }
    }
  });
  for (size_t n : coveredPerBand) stats.coveredPixels += n;
  stats.resolveMs = stopwatch.Lap();
  return stats;
}

}  // namespace ssgi
