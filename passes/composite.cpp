#include "passes/composite.h"

#include <algorithm>
#include <vector>

#include "core/brdf.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi {

CompositeStats RunComposite(const CompositeInputs& in, CompositeOutputs& out) {
  Stopwatch stopwatch;
  const int width = in.gbuffer.width(), height = in.gbuffer.height();
  out.indirect = MakePlane3<float>(width, height, 0.0f);
  out.result = MakePlane3<float>(width, height, 0.0f);
  ParallelForRowBands("composite", size_t(height), [&](size_t, size_t yBegin, size_t yEnd) {
    for (size_t y = yBegin; y < yEnd; ++y) {
      const uint32_t* w0 = in.gbuffer.word[0].ConstRow(y);
      const uint32_t* w1 = in.gbuffer.word[1].ConstRow(y);
      const uint32_t* w2 = in.gbuffer.word[2].ConstRow(y);
      const float* confidence = in.confidence.ConstRow(y);
      for (int x = 0; x < width; ++x) {
        glm::vec3 indirect(0.0f);
        if (confidence[x] > 0.0f && UnpackDepth(w2[x]) != kBackgroundDepth) {
          const SurfaceMaterial material{UnpackAlbedo(w0[x]), UnpackMetallic(w0[x]), UnpackRoughness(w1[x])};
          const glm::vec3 normal = UnpackNormal(w1[x], in.gbuffer.normalEncoding);
          const glm::vec3 toViewer = glm::normalize(-in.view.PixelRay(float(x) + 0.5f, float(y) + 0.5f).direction);
          const float nDotV = std::clamp(glm::dot(normal, toViewer), 0.0f, 1.0f);
          const float fade = std::clamp((in.roughnessCutoff - material.roughness) / kRoughnessFadeWidth, 0.0f, 1.0f);
          const glm::vec3 weight =
              SpecularWeight(SpecularF0(material), nDotV, material.roughness) * (confidence[x] * fade);
          for (int c = 0; c < 3; ++c) indirect[c] = in.reflected.c[c].ConstRow(y)[x] * weight[c];
        }
        for (int c = 0; c < 3; ++c) {
          out.indirect.c[c].MutableRow(y)[x] = indirect[c];
          out.result.c[c].MutableRow(y)[x] = in.direct.c[c].ConstRow(y)[x] + indirect[c];
        }
      }
    }
  });
  CompositeStats stats;
  stats.pixels = size_t(width) * size_t(height);
  stats.ms = stopwatch.Lap();
  return stats;
}

}  // namespace ssgi
