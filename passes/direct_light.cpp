#include "passes/direct_light.h"

#include <algorithm>
#include <vector>

#include "core/brdf.h"
#include "core/lighting.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi {

DirectLightStats RunDirectLight(const DirectLightInputs& in, const DirectLightParams& params,
                                DirectLightOutputs& out) {
  Stopwatch stopwatch;
  const int width = in.gbuffer.width(), height = in.gbuffer.height();
  const std::vector<PreparedLight> lights = PrepareLights(in.scene, in.view.view);
  const NormalEncoding encoding = in.gbuffer.normalEncoding;
  const glm::vec3 background = params.background;
  out.radiance = MakePlane3<float>(width, height, 0.0f);
  std::vector<size_t> shadedPerBand(RowBandCount(size_t(height)), 0);

  ParallelForRowBands("direct_light", size_t(height), [&](size_t band, size_t yBegin, size_t yEnd) {
    for (size_t y = yBegin; y < yEnd; ++y) {
      const uint32_t* w0 = in.gbuffer.word[0].ConstRow(y);
      const uint32_t* w1 = in.gbuffer.word[1].ConstRow(y);
      const uint32_t* w2 = in.gbuffer.word[2].ConstRow(y);
      const float* visibility = in.lightVisibility ? in.lightVisibility->ConstRow(y) : nullptr;
      float* outRgb[3] = {out.radiance.c[0].MutableRow(y), out.radiance.c[1].MutableRow(y),
                          out.radiance.c[2].MutableRow(y)};
      for (int x = 0; x < width; ++x) {
        const float depth = UnpackDepth(w2[x]);
        glm::vec3 radiance = background;
        if (depth != kBackgroundDepth) {
          ++shadedPerBand[band];
          const ViewProjection::Ray ray = in.view.PixelRay(float(x) + 0.5f, float(y) + 0.5f);
          const glm::vec3 position = ray.origin + ray.direction * depth;
          const glm::vec3 toViewer = glm::normalize(-ray.direction);
          const glm::vec3 normal = UnpackNormal(w1[x], encoding);
          const SurfaceMaterial material{UnpackAlbedo(w0[x]), UnpackMetallic(w0[x]), UnpackRoughness(w1[x])};
          const float alpha = material.roughness * material.roughness;
          radiance = glm::vec3(0.0f);
          for (size_t i = 0; i < lights.size(); ++i) {
            const LightAtPoint l = Evaluate(lights[i], position);
            glm::vec3 contribution =
                BrdfCosine(material, WidenedAlpha(alpha, l.tanAngularRadius), normal, toViewer, l.toLight) *
                l.irradiance;
            if (visibility && i == in.shadowedLight) contribution *= visibility[x];
            radiance += contribution;
          }
        }
        for (int c = 0; c < 3; ++c) outRgb[c][x] = radiance[c];
      }
    }
  });

  DirectLightStats stats;
  for (size_t n : shadedPerBand) stats.pixels += n;
  stats.ms = stopwatch.Lap();
  return stats;
}

}  // namespace ssgi
