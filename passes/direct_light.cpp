#include "passes/direct_light.h"

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/brdf.h"
#include "core/check.h"
#include "core/color.h"
#include "core/lighting.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi {

size_t DirectLightRowScalar(const DirectLightContext& context, const uint32_t* word0, const uint32_t* word1,
                            const uint32_t* word2, const float* visibility, size_t y, int width, float* red,
                            float* green, float* blue) {
  float* outRgb[3] = {red, green, blue};
  size_t shaded = 0;
  for (int x = 0; x < width; ++x) {
    const float depth = UnpackDepth(word2[x]);
    glm::vec3 radiance = context.background;
    if (depth != kBackgroundDepth) {
      ++shaded;
      const ViewProjection::Ray ray = context.view.PixelRay(float(x) + 0.5f, float(y) + 0.5f);
      const glm::vec3 position = ray.origin + ray.direction * depth;
      const glm::vec3 toViewer = glm::normalize(-ray.direction);
      const glm::vec3 normal = UnpackNormal(word1[x], context.normalEncoding);
      const SurfaceMaterial material{UnpackAlbedo(word0[x]), UnpackMetallic(word0[x]), UnpackRoughness(word1[x])};
      const float alpha = material.roughness * material.roughness;
      radiance = glm::vec3(0.0f);
      for (size_t i = 0; i < context.lightCount; ++i) {
        const LightAtPoint l = Evaluate(context.lights[i], position);
        glm::vec3 contribution =
            DiskLightBrdfCosine(material, alpha, normal, toViewer, l.toLight, l.tanAngularRadius) * l.irradiance;
        if (visibility && i == context.shadowedLight) contribution *= visibility[x];
        radiance += contribution;
      }
    }
    for (int c = 0; c < 3; ++c) outRgb[c][x] = SanitizeRadiance(radiance[c]);
  }
  return shaded;
}

DirectLightStats RunDirectLight(const DirectLightInputs& in, const DirectLightParams& params,
                                DirectLightOutputs& out, KernelPath kernels) {
  Stopwatch stopwatch;
  const int width = in.gbuffer.width(), height = in.gbuffer.height();
  std::vector<PreparedLight> lights;
  size_t shadowedLight = SIZE_MAX;  // its index among the shaded lights; none when not shaded
  const std::vector<PreparedLight> prepared = PrepareLights(in.scene, in.view.view);
  if (in.shadeLights) SSGI_CHECK_EQ(in.shadeLights->size(), prepared.size());
  for (size_t i = 0; i < prepared.size(); ++i) {
    if (in.shadeLights && !(*in.shadeLights)[i]) continue;
    if (i == in.shadowedLight) shadowedLight = lights.size();
    lights.push_back(prepared[i]);
  }
  const DirectLightContext context{
      in.view, lights.data(), lights.size(), shadowedLight, in.gbuffer.normalEncoding, params.background,
  };
  const Plane<float>* visibility = shadowedLight != SIZE_MAX ? in.lightVisibility : nullptr;
  const auto row = kernels == KernelPath::kSimd ? DirectLightRowSimd : DirectLightRowScalar;
  ReusePlane3(out.radiance, size_t(width), size_t(height));
  std::vector<size_t> shadedPerBand(RowBandCount(size_t(height)), 0);

  ParallelForRowBands("direct_light", size_t(height), [&](size_t band, size_t yBegin, size_t yEnd) {
    // Counted locally: neighbouring bands' counters share a cache line.
    size_t shaded = 0;
    for (size_t y = yBegin; y < yEnd; ++y) {
      shaded +=
          row(context, in.gbuffer.word[GBufferWord::kAlbedoMetallic].ConstRow(y),
              in.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(y),
              in.gbuffer.word[GBufferWord::kDepth].ConstRow(y), visibility ? visibility->ConstRow(y) : nullptr, y,
              width, out.radiance.c[0].MutableRow(y), out.radiance.c[1].MutableRow(y), out.radiance.c[2].MutableRow(y));
    }
    shadedPerBand[band] = shaded;
  });

  DirectLightStats stats;
  for (size_t n : shadedPerBand) stats.pixels += n;
  stats.ms = stopwatch.Lap();
  return stats;
}

}  // namespace ssgi
