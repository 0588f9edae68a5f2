#include "passes/composite.h"

#include <algorithm>
#include <vector>

#include "core/brdf.h"
#include "core/check.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi {

void CompositeRowScalar(const CompositeContext& context, const CompositeRow& row, size_t y, int xBegin, int xEnd) {
  for (int x = xBegin; x < xEnd; ++x) {
    if (context.inPlace && !(row.confidence[x] > 0.0f)) continue;
    glm::vec3 indirect(0.0f);
    if (row.confidence[x] > 0.0f && UnpackDepth(row.word2[x]) != kBackgroundDepth) {
      const SurfaceMaterial material{UnpackAlbedo(row.word0[x]), UnpackMetallic(row.word0[x]),
                                     UnpackRoughness(row.word1[x])};
      const glm::vec3 normal = UnpackNormal(row.word1[x], context.normalEncoding);
      const glm::vec3 toViewer = glm::normalize(-context.view.PixelRay(float(x) + 0.5f, float(y) + 0.5f).direction);
      const float nDotV = std::clamp(glm::dot(normal, toViewer), 0.0f, 1.0f);
      const float fade = std::clamp((context.roughnessCutoff - material.roughness) / kRoughnessFadeWidth, 0.0f, 1.0f);
      const glm::vec3 weight =
          SpecularWeight(SpecularF0(material), nDotV, material.roughness) * (row.confidence[x] * fade);
      for (int c = 0; c < 3; ++c) indirect[c] = row.reflected[c][x] * weight[c];
    }
    for (int c = 0; c < 3; ++c) {
      row.indirect[c][x] = indirect[c];
      row.result[c][x] = row.direct[c][x] + indirect[c];
    }
  }
}

CompositeStats RunComposite(const CompositeInputs& in, CompositeOutputs& out, KernelPath kernels) {
  Stopwatch stopwatch;
  const int width = in.gbuffer.width(), height = in.gbuffer.height();
  ReusePlane3(out.indirect, size_t(width), size_t(height));
  ReusePlane3(out.result, size_t(width), size_t(height));
  const bool inPlace = &in.direct == &out.result && &in.reflected == &out.indirect;
  const CompositeContext context{in.view, in.gbuffer.normalEncoding, in.roughnessCutoff, inPlace};
  const auto composite = kernels == KernelPath::kSimd ? CompositeRowSimd : CompositeRowScalar;
  SSGI_CHECK(in.tiles == nullptr || in.tiles->Fits(width, height));
  ParallelForRowBands("composite", size_t(height), [&](size_t, size_t yBegin, size_t yEnd) {
    for (size_t y = yBegin; y < yEnd; ++y) {
      const CompositeRow row{
          in.gbuffer.word[GBufferWord::kAlbedoMetallic].ConstRow(y),
          in.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(y),
          in.gbuffer.word[GBufferWord::kDepth].ConstRow(y),
          in.confidence.ConstRow(y),
          {in.direct.c[0].ConstRow(y), in.direct.c[1].ConstRow(y), in.direct.c[2].ConstRow(y)},
          {in.reflected.c[0].ConstRow(y), in.reflected.c[1].ConstRow(y), in.reflected.c[2].ConstRow(y)},
          {out.indirect.c[0].MutableRow(y), out.indirect.c[1].MutableRow(y), out.indirect.c[2].MutableRow(y)},
          {out.result.c[0].MutableRow(y), out.result.c[1].MutableRow(y), out.result.c[2].MutableRow(y)},
      };
      // Outside the mask the kernel would store indirect 0 and result direct + 0; in place both are
      // already there.
      ForEachTileRun(
          in.tiles, int(y), width, [&](int xBegin, int xEnd) { composite(context, row, y, xBegin, xEnd); },
          [&](int xBegin, int xEnd) {
            if (inPlace) return;
            for (int c = 0; c < 3; ++c) {
              std::fill(row.indirect[c] + xBegin, row.indirect[c] + xEnd, 0.0f);
              std::transform(row.direct[c] + xBegin, row.direct[c] + xEnd, row.result[c] + xBegin,
                             [](float direct) { return direct + 0.0f; });
            }
          });
    }
  });
  CompositeStats stats;
  stats.pixels = size_t(width) * size_t(height);
  stats.ms = stopwatch.Lap();
  return stats;
}

}  // namespace ssgi
