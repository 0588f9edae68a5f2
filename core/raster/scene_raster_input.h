// A scene's mesh prepared for the rasterizer (core/raster/raster.h) from one view: the camera for the
// G-buffer, a light for a shadow map (docs/pipeline.md §G-buffer, §Shadow map and blocker search).
#pragma once

#include <memory>

#include "core/camera.h"
#include "core/raster/raster.h"
#include "core/scene.h"
#include "core/surface.h"

namespace ssgi {

// Per-triangle flags (back faces culled unless the material is two-sided or `cullBackFaces` is
// false; alpha test where the material has an alpha texture) and the alpha test itself, evaluated
// with the same surface interpolation and texture lookup as the G-buffer resolve (Resolver()).
// `scene` and `view` must outlive it.
class SceneRasterInput {
 public:
  SceneRasterInput(const Scene& scene, const ViewProjection& view, bool cullBackFaces);
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

}  // namespace ssgi
