// The port's shadow passes (docs/pipeline.md §Shadow map and blocker search, §Shadow filter): the
// light's camera fitted to the receivers, the shadow map as a depth-only pass on GL's rasterizer
// (tests/port/gl_raster.h), the blocker search into word 3 and the SSABSS / SSPCSS filter, the last
// two as compute shaders.
#pragma once

#include <optional>
#include <vector>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/scene.h"
#include "passes/shadow_filter.h"
#include "passes/shadow_map.h"
#include "tests/port/gl_objects.h"
#include "tests/port/gl_raster.h"

namespace ssgi::port {

// The G-buffer as the shadow passes read it.
struct ShadowInputs {
  const Scene& scene;
  const SceneBuffers& sceneBuffers;
  const ViewProjection& camera;
  NormalEncoding encoding;
  const Buffer& word1;
  const Buffer& word2;
};

struct ShadowMapResult {
  ViewProjection lightView;
  // resolution^2 keys, rows from the top, 0 where nothing was drawn (all 0 where no pixel receives);
  // no words where not rasterized.
  Buffer depthKey;
};

// §Light camera for the shadowed light (the first shadow-casting one), and where `rasterize`,
// §Shadow-map raster on GL.
ShadowMapResult RunPortShadowMap(const ShadowInputs& in, const ShadowMapParams& params, bool rasterize);

// §Blocker search: word 3 of every pixel against `depthKey` (the port's map or the oracle's).
Buffer RunPortBlockerSearch(const ShadowInputs& in, const ShadowMapParams& params, const ViewProjection& lightView,
                            const Buffer& depthKey);

// §Shadow filter: the visibility of the shadowed light from words 1-3.
Buffer RunPortShadowFilter(const ShadowInputs& in, const ShadowFilterParams& params, const Buffer& word3);

}  // namespace ssgi::port
