// A scene's mesh prepared for the rasterizer (core/raster/raster.h) from one view: the camera for the
// G-buffer, a light for a shadow map (docs/pipeline.md §G-buffer, §Shadow map and blocker search).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/camera.h"
#include "core/closed_surfaces.h"
#include "core/raster/raster.h"
#include "core/scene.h"
#include "core/surface.h"

namespace ssgi {

// Per-triangle flags (back faces culled unless the material is two-sided or `cullBackFaces` is
// false, and those of the `closed` surfaces CulledClosedSurfaces names; alpha test where the
// material has an alpha texture) and the alpha test itself, evaluated with the same surface
// interpolation and texture lookup as the G-buffer resolve (Resolver()). `scene`, `view` and
// `closed` must outlive it.
class SceneRasterInput {
 public:
  SceneRasterInput(const Scene& scene, const ViewProjection& view, bool cullBackFaces,
                   const ClosedSurfaces* closed = nullptr);
  ~SceneRasterInput();
  SceneRasterInput(const SceneRasterInput&) = delete;
  SceneRasterInput& operator=(const SceneRasterInput&) = delete;
  const RasterInput& Get() const { return input_; }
  // The mesh's surface seen from `view`, for shading what the rasterizer found visible.
  const SurfaceResolver& Resolver() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  RasterInput input_;
};

// Per closed surface of `closed` (found in scene.mesh): 1 where a raster from `view` may cull its
// back faces and still find the same nearest surfaces: no triangle of it has a cut-out (an alpha
// test shows its inside through the holes), and every corner of its box lies beyond the view's near
// plane (a viewpoint inside it, or a near plane through it, sees its inside).
std::vector<uint8_t> CulledClosedSurfaces(const Scene& scene, const ClosedSurfaces& closed, const ViewProjection& view);

}  // namespace ssgi
