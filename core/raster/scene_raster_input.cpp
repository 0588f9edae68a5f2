#include "core/raster/scene_raster_input.h"

#include <algorithm>
#include <bit>
#include <functional>
#include <vector>

#include "core/check.h"
#include "core/texture.h"

namespace ssgi {
namespace {

float AlphaChannel(const Texture& texture, const glm::vec4& texel) {
  // Grey+alpha and RGBA images carry the mask in alpha; grey and RGB masks in their first channel.
  return texture.sourceChannels == 2 || texture.sourceChannels == 4 ? texel.w : texel.x;
}

struct AlphaTestContext {
  const Scene* scene;
  const SurfaceResolver* resolver;
};

// AlphaTest::passes: the samples of the block whose alpha reaches the material's cut-off.
uint64_t PassesAlphaTest(const void* context, uint32_t triangle, int x0, int y0, uint64_t samples) {
  const auto& ctx = *static_cast<const AlphaTestContext*>(context);
  const Material& material = ctx.scene->materials[ctx.scene->mesh.materials[triangle]];
  const Texture& texture = ctx.scene->textures[material.alphaTexture];
  uint64_t passed = 0;
  for (uint64_t rest = samples; rest != 0; rest &= rest - 1) {
    const int sample = std::countr_zero(rest);
    const SurfacePoint s =
        ctx.resolver->At(triangle, x0 + sample % kRasterBlockSize, y0 + sample / kRasterBlockSize, true);
    if (AlphaChannel(texture, SampleTexture(texture, s.uv, s.uvFootprint)) >= material.alphaCutoff)
      passed |= rest & -rest;
  }
  return passed;
}

}  // namespace

struct SceneRasterInput::Impl {
  Impl(const Scene& scene, const ViewProjection& view) : resolver(scene, view), alphaContext{&scene, &resolver} {}
  SurfaceResolver resolver;
  std::vector<uint8_t> flags;
  AlphaTestContext alphaContext;
};

std::vector<uint8_t> CulledClosedSurfaces(const Scene& scene, const ClosedSurfaces& closed,
                                          const ViewProjection& view) {
  std::vector<uint8_t> culled(closed.lo.size(), 1);
  for (size_t s = 0; s < culled.size(); ++s) {
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 p(corner & 1 ? closed.hi[s].x : closed.lo[s].x, corner & 2 ? closed.hi[s].y : closed.lo[s].y,
                        corner & 4 ? closed.hi[s].z : closed.lo[s].z);
      if (!(-(view.view * glm::vec4(p, 1.0f)).z > view.nearPlane)) culled[s] = 0;
    }
  }
  for (size_t t = 0; t < closed.surface.size(); ++t) {
    if (closed.surface[t] != ClosedSurfaces::kOpen &&
        scene.materials[scene.mesh.materials[t]].alphaTexture != kNoTexture)
      culled[closed.surface[t]] = 0;
  }
  return culled;
}

SceneRasterInput::SceneRasterInput(const Scene& scene, const ViewProjection& view, bool cullBackFaces,
                                   const ClosedSurfaces* closed)
    : impl_(std::make_unique<Impl>(scene, view)) {
  SSGI_CHECK(!closed || closed->surface.size() == scene.mesh.TriangleCount());
  std::vector<uint8_t> materialFlags(scene.materials.size());
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    const Material& material = scene.materials[m];
    materialFlags[m] = uint8_t((cullBackFaces && !material.twoSided ? kTriangleCullBackFace : 0) |
                               (material.alphaTexture != kNoTexture ? kTriangleAlphaTested : 0));
  }
  // One mask for every triangle where the materials agree (a scanned model, the benchmarks' knots):
  // no per-triangle array to fill, a millisecond of one thread per frame for a million triangles.
  const std::vector<uint8_t> culled = closed ? CulledClosedSurfaces(scene, *closed, view) : std::vector<uint8_t>();
  const bool cullsClosed = std::find(culled.begin(), culled.end(), 1) != culled.end();
  const bool uniform = !cullsClosed && std::adjacent_find(materialFlags.begin(), materialFlags.end(),
                                                          std::not_equal_to<>()) == materialFlags.end();
  if (!uniform) {
    impl_->flags.resize(scene.mesh.TriangleCount());
    for (size_t t = 0; t < impl_->flags.size(); ++t) {
      impl_->flags[t] = materialFlags[scene.mesh.materials[t]];
      if (cullsClosed && closed->surface[t] != ClosedSurfaces::kOpen && culled[closed->surface[t]])
        impl_->flags[t] |= kTriangleCullBackFace;
    }
  }
  input_.positions = scene.mesh.positions.data();
  input_.vertexCount = scene.mesh.positions.size();
  input_.indices = scene.mesh.indices.data();
  input_.triangleCount = scene.mesh.TriangleCount();
  input_.triangleFlags = uniform ? nullptr : impl_->flags.data();
  input_.uniformFlags = uniform && !materialFlags.empty() ? materialFlags.front() : uint8_t(0);
  input_.alphaTest = {&PassesAlphaTest, &impl_->alphaContext};
}

SceneRasterInput::~SceneRasterInput() = default;

const SurfaceResolver& SceneRasterInput::Resolver() const { return impl_->resolver; }

}  // namespace ssgi
