#include "passes/composite.h"

#include <algorithm>
#include <vector>

#include "core/brdf.h"
#include "core/check.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi {

void CompositeRowScalar(const CompositeContext& context, const CompositeRow& row, size_t y, int xBegin, int xEnd) {
  const bool sky = context.environment != nullptr;
  const bool bounce = row.bounce[0] != nullptr;
  for (int x = xBegin; x < xEnd; ++x) {
    const float confidence = row.confidence ? row.confidence[x] : 0.0f;
    if (context.inPlace && !sky && !bounce && !(confidence > 0.0f)) continue;
    glm::vec3 base(row.direct[0][x], row.direct[1][x], row.direct[2][x]);
    glm::vec3 indirect(0.0f);
    if ((confidence > 0.0f || sky || bounce) && UnpackDepth(row.word2[x]) != kBackgroundDepth) {
      const SurfaceMaterial material{UnpackAlbedo(row.word0[x]), UnpackMetallic(row.word0[x]),
                                     UnpackRoughness(row.word1[x])};
      if (confidence > 0.0f || sky) {
        const glm::vec3 normal = UnpackNormal(row.word1[x], context.normalEncoding);
        const glm::vec3 toViewer = glm::normalize(-context.view.PixelRay(float(x) + 0.5f, float(y) + 0.5f).direction);
        const float nDotV = std::clamp(glm::dot(normal, toViewer), 0.0f, 1.0f);
        const float fade = std::clamp((context.roughnessCutoff - material.roughness) / kRoughnessFadeWidth, 0.0f, 1.0f);
        const glm::vec3 specular = SpecularWeight(SpecularF0(material), nDotV, material.roughness);
        if (confidence > 0.0f) {
          const glm::vec3 weight = specular * (confidence * fade);
          for (int c = 0; c < 3; ++c) indirect[c] = row.reflected[c][x] * weight[c];
        }
        if (sky) {
          // The share the trace did not see, towards the mirror direction r = 2 (n.v) n - v.
          const float unseen = 1.0f - confidence * fade;
          const float share = unseen * row.skyVisibility[x];
          const glm::vec3 reflection = normal * (2.0f * glm::dot(normal, toViewer)) - toViewer;
          const glm::vec3 environment =
              PrefilteredEnvironment(*context.environment, context.viewToWorld * reflection, material.roughness);
          for (int c = 0; c < 3; ++c) indirect[c] = indirect[c] + environment[c] * (specular[c] * share);
          // The surfaces around, which the sky's visibility took away from the environment's light.
          if (row.skyReflected[0])
            for (int c = 0; c < 3; ++c) indirect[c] = indirect[c] + row.skyReflected[c][x] * (specular[c] * unseen);
        }
      }
      if (bounce) {
        // A Lambertian surface reflects its diffuse albedo times E / pi.
        const glm::vec3 diffuseAlbedo = material.albedo * (1.0f - material.metallic);
        for (int c = 0; c < 3; ++c) indirect[c] = indirect[c] + row.bounce[c][x] * diffuseAlbedo[c];
        // lit holds the sky's diffuse light unoccluded by the surfaces around the pixel: take away
        // the share (1 - visibility) of it that they cover.
        if (row.skyDiffuse[0]) {
          const float darkening = row.ambientVisibility[x] - 1.0f;
          for (int c = 0; c < 3; ++c) base[c] = base[c] + row.skyDiffuse[c][x] * darkening;
        }
      }
    }
    for (int c = 0; c < 3; ++c) {
      if (row.indirect[c]) row.indirect[c][x] = indirect[c];
      row.result[c][x] = base[c] + indirect[c];
    }
  }
}

CompositeStats RunComposite(const CompositeInputs& in, CompositeOutputs& out, KernelPath kernels) {
  Stopwatch stopwatch;
  const int width = in.gbuffer.width(), height = in.gbuffer.height();
  if (in.keepIndirect) ReusePlane3(out.indirect, size_t(width), size_t(height));
  ReusePlane3(out.result, size_t(width), size_t(height));
  const bool inPlace = &in.direct == &out.result && in.reflected == &out.indirect;
  SSGI_CHECK((in.reflected == nullptr) == (in.confidence == nullptr));
  SSGI_CHECK(in.environment == nullptr || (in.skyVisibility != nullptr && in.tiles == nullptr));
  SSGI_CHECK(in.skyReflected == nullptr || in.environment != nullptr);
  SSGI_CHECK(in.bounce == nullptr || in.tiles == nullptr);
  SSGI_CHECK((in.skyDiffuse == nullptr) == (in.ambientVisibility == nullptr));
  SSGI_CHECK(in.skyDiffuse == nullptr || in.bounce != nullptr);
  const CompositeContext context{in.view,
                                 in.gbuffer.normalEncoding,
                                 in.roughnessCutoff,
                                 inPlace,
                                 in.environment,
                                 glm::mat3(glm::inverse(in.view.view))};
  const auto composite = kernels == KernelPath::kSimd ? CompositeRowSimd : CompositeRowScalar;
  SSGI_CHECK(in.tiles == nullptr || in.tiles->Fits(width, height));
  ParallelForRowBands("composite", size_t(height), [&](size_t, size_t yBegin, size_t yEnd) {
    for (size_t y = yBegin; y < yEnd; ++y) {
      const CompositeRow row{
          in.gbuffer.word[GBufferWord::kAlbedoMetallic].ConstRow(y),
          in.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(y),
          in.gbuffer.word[GBufferWord::kDepth].ConstRow(y),
          in.confidence ? in.confidence->ConstRow(y) : nullptr,
          in.skyVisibility ? in.skyVisibility->ConstRow(y) : nullptr,
          {in.skyReflected ? in.skyReflected->c[0].ConstRow(y) : nullptr,
           in.skyReflected ? in.skyReflected->c[1].ConstRow(y) : nullptr,
           in.skyReflected ? in.skyReflected->c[2].ConstRow(y) : nullptr},
          {in.direct.c[0].ConstRow(y), in.direct.c[1].ConstRow(y), in.direct.c[2].ConstRow(y)},
          {in.reflected ? in.reflected->c[0].ConstRow(y) : nullptr,
           in.reflected ? in.reflected->c[1].ConstRow(y) : nullptr,
           in.reflected ? in.reflected->c[2].ConstRow(y) : nullptr},
          {in.keepIndirect ? out.indirect.c[0].MutableRow(y) : nullptr,
           in.keepIndirect ? out.indirect.c[1].MutableRow(y) : nullptr,
           in.keepIndirect ? out.indirect.c[2].MutableRow(y) : nullptr},
          {out.result.c[0].MutableRow(y), out.result.c[1].MutableRow(y), out.result.c[2].MutableRow(y)},
          {in.bounce ? in.bounce->c[0].ConstRow(y) : nullptr, in.bounce ? in.bounce->c[1].ConstRow(y) : nullptr,
           in.bounce ? in.bounce->c[2].ConstRow(y) : nullptr},
          {in.skyDiffuse ? in.skyDiffuse->c[0].ConstRow(y) : nullptr,
           in.skyDiffuse ? in.skyDiffuse->c[1].ConstRow(y) : nullptr,
           in.skyDiffuse ? in.skyDiffuse->c[2].ConstRow(y) : nullptr},
          in.ambientVisibility ? in.ambientVisibility->ConstRow(y) : nullptr,
      };
      // Outside the mask the kernel would store indirect 0 and result direct + 0; in place both are
      // already there.
      ForEachTileRun(
          in.tiles, int(y), width, [&](int xBegin, int xEnd) { composite(context, row, y, xBegin, xEnd); },
          [&](int xBegin, int xEnd) {
            if (inPlace) return;
            for (int c = 0; c < 3; ++c) {
              if (row.indirect[c]) std::fill(row.indirect[c] + xBegin, row.indirect[c] + xEnd, 0.0f);
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
