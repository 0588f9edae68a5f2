// G-buffer pass (DESIGN.md §3-4, docs/pipeline.md §G-buffer): rasterizes the scene's triangles into a
// visibility buffer (core/raster.h, core/scene_raster_input.h), then resolves each visible pixel
// once: barycentrics from the view ray through the pixel centre and the original (unclipped)
// triangle, interpolated normal and UV, mip-mapped texture lookups with the UV footprint of the
// neighbouring pixels' rays (core/surface.h), and packs the 128-bit G-buffer. Alpha cut-out (map_d)
// is tested during rasterization.
#pragma once

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/raster.h"
#include "core/scene.h"

namespace ssgi {

struct GBufferParams {
  NormalEncoding normalEncoding = NormalEncoding::kOct24;
};

struct GBufferInputs {
  const Scene& scene;
  const ViewProjection& view;  // perspective camera view of the G-buffer's size
};

struct GBufferOutputs {
  GBuffer gbuffer;             // words 0-2 filled; word 3 set to kShadowLit
  VisibilityBuffer visibility; // the triangle index per pixel (for dumps and tests)
};

struct GBufferStats {
  RasterStats raster;
  double rasterMs = 0.0;
  double resolveMs = 0.0;
  size_t coveredPixels = 0;
};

GBufferStats RunGBuffer(const GBufferInputs& in, const GBufferParams& params, GBufferOutputs& out);

}  // namespace ssgi
