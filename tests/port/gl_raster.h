// The port's rasterizing passes on GL's own rasterizer (tests/port/README.md): the scene uploaded as
// surface.glsl reads it, the visibility pass (GL's coverage, the oracle's depth key and triangle
// index), the G-buffer resolve on it, and the conventional G-buffer pass (words from interpolated
// varyings). The shadow map (tests/port/gl_shadows.h) rasterizes with the same visibility pass.
#pragma once

#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/scene.h"
#include "tests/port/gl_objects.h"

namespace ssgi::port {

// The scene's mesh, materials and textures in the layout of surface.glsl; Bind() binds them there.
class SceneBuffers {
 public:
  explicit SceneBuffers(const Scene& scene);
  void Bind() const;
  size_t triangles() const { return triangles_; }
  const Buffer& indices() const { return indices_; }

 private:
  size_t triangles_;
  Buffer positions_, normals_, uvs_, indices_, triangleMaterials_, materials_, textures_, texels_;
};

// surface.glsl's view uniforms (and common.glsl's imageSize and tanHalf) for `view`; SetRasterView
// also raster.glsl's, the vertices snapped to `snapBits` sub-pixel bits (8: GL's own grid alone).
void SetSurfaceView(const Program& program, const ViewProjection& view);
void SetRasterView(const Program& program, const ViewProjection& view, int snapBits = 8);

// A rasterized target: per pixel, row by row from the top, the triangle index (kNoTriangle where
// nothing was drawn) and the depth key (0 there). `triangle` is empty (no words) for depth-only.
struct VisibilityTargets {
  Buffer triangle, depthKey;
};

enum class RasterKind { kVisibility, kDepthOnly };

// §Rasterizer on GL: every triangle of the scene seen from `view` (the camera, or a light at the
// map's resolution), back faces of one-sided materials culled where `cullBackFaces` and those of the
// triangles `closedCulled` marks (per triangle, not 0: cull; empty: none), the vertices snapped to
// `snapBits` sub-pixel bits first where fewer than GL's 8 (an emulated coarser rasterizer).
VisibilityTargets RunVisibilityPass(const SceneBuffers& scene, const ViewProjection& view, bool cullBackFaces,
                                    RasterKind kind, int snapBits = 8, const std::vector<uint32_t>& closedCulled = {});

// G-buffer words 0-2 (word 3 is the shadow pass's) and the visibility buffer they came from.
struct PortGBuffer {
  std::vector<Buffer> words;  // 0, 1, 2
  VisibilityTargets visibility;
};

// How the port makes the G-buffer (tests/port/README.md): the oracle's resolve on a visibility
// buffer, or a conventional pass whose fragment shader writes the packed words.
enum class GBufferForm { kVisibility, kConventional };

PortGBuffer RunGBufferPass(const SceneBuffers& scene, const ViewProjection& camera, NormalEncoding encoding,
                           float specularAaKappa, GBufferForm form, int snapBits);

}  // namespace ssgi::port
