// The port's sky visibility volume (docs/pipeline.md §Sky light, "The sky visibility volume"): the
// scene rasterized depth-only, both faces, into an orthographic map per Fibonacci direction on GL's
// rasterizer (tests/port/gl_raster.h), and sky_volume.comp testing every cell centre against each
// map in the directions' order.
#pragma once

#include "core/scene.h"
#include "passes/sky_light.h"
#include "tests/port/gl_objects.h"
#include "tests/port/gl_raster.h"

namespace ssgi::port {

// The coefficients of `grid` (SkyVisibilityGrid's), four per cell, x fastest, then y, then z.
Buffer RunPortSkyVolume(const SceneBuffers& scene, const SkyVisibilityVolume& grid);

}  // namespace ssgi::port
