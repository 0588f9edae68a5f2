#include "passes/ssr_cone.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "core/check.h"
#include "core/parallel.h"
#include "core/pyramid.h"
#include "core/stopwatch.h"

namespace ssgi {
namespace {

// Bilinear fetch of one level at level-0 pixel coordinates (pixel centres at +0.5), clamp to edge.
// A level's floor-halved size maps onto the full image by the per-axis size ratio, the same area
// a level texel averages (color_pyramid.h).
glm::vec3 SampleLevel(const ColorPyramid& pyramid, int level, float x, float y) {
  const Plane3<float>& image = pyramid.levels[size_t(level)];
  const Plane<float>& base = pyramid.levels[0].c[0];
  const int width = int(image.c[0].xsize()), height = int(image.c[0].ysize());
  const float u = x * (float(width) / float(base.xsize())) - 0.5f;
  const float v = y * (float(height) / float(base.ysize())) - 0.5f;
  const float uFloor = std::floor(u), vFloor = std::floor(v);
  const float fu = u - uFloor, fv = v - vFloor;
  const int x0 = std::clamp(int(uFloor), 0, width - 1), x1 = std::clamp(int(uFloor) + 1, 0, width - 1);
  const int y0 = std::clamp(int(vFloor), 0, height - 1), y1 = std::clamp(int(vFloor) + 1, 0, height - 1);
  glm::vec3 result;
  for (int c = 0; c < 3; ++c) {
    const float* row0 = image.c[c].ConstRow(size_t(y0));
    const float* row1 = image.c[c].ConstRow(size_t(y1));
    const float top = row0[x0] + (row0[x1] - row0[x0]) * fu;
    const float bottom = row1[x0] + (row1[x1] - row1[x0]) * fu;
    result[c] = top + (bottom - top) * fv;
  }
  return result;
}

// Trilinear fetch for a circle of the given diameter (px, >= 1): level = log2(diameter), the level
// whose texel is as wide as the circle. log2 is piecewise linear between powers of two (frexp is
// exact), so no libm transcendental runs per pixel (docs/design.md §11); exact at every level.
glm::vec3 SampleCircle(const ColorPyramid& pyramid, float x, float y, float diameter) {
  int exponent = 0;
  const float mantissa = std::frexp(diameter, &exponent);  // diameter = mantissa * 2^exponent, [0.5, 1)
  const int level = exponent - 1;
  const int lastLevel = int(pyramid.levels.size()) - 1;
  if (level >= lastLevel) return SampleLevel(pyramid, lastLevel, x, y);
  const float t = 2.0f * mantissa - 1.0f;
  const glm::vec3 fine = SampleLevel(pyramid, level, x, y);
  const glm::vec3 coarse = SampleLevel(pyramid, level + 1, x, y);
  return fine + (coarse - fine) * t;
}

struct ConeSample {
  glm::vec3 radiance;
  int samples;
};

// Uludag's loop: the hit is the apex-opposite base of an isosceles triangle of height h (screen
// distance origin -> hit) and apex angle 2 theta. Circle i is the incircle of the remaining
// triangle (height adj, base a = 2 adj tan theta): r = a (sqrt(a^2 + 4 adj^2) - a) / (4 adj)
// = adj t (sqrt(1 + t^2) - t); its centre is adj - r from the origin; the next triangle ends at the
// circle's near side (adj -= 2 r). Coverage of circle i = (r / (h t))^2, its area over the cone's
// footprint disk at the hit; the last circle gets only the coverage left below 1 (Uludag's
// remaining alpha), and the sum is normalised by the coverage taken.
ConeSample TraceCone(const ColorPyramid& pyramid, glm::vec2 origin, glm::vec2 hit, float tanTheta,
                     int maxSamples) {
  const glm::vec2 delta = hit - origin;
  const float h = std::sqrt(delta.x * delta.x + delta.y * delta.y);
  if (!(h >= kConeMinHeight)) return {SampleLevel(pyramid, 0, hit.x, hit.y), 1};
  const glm::vec2 direction = delta / h;
  const float inRadiusPerHeight = tanTheta * (std::sqrt(1.0f + tanTheta * tanTheta) - tanTheta);
  const float footprintRadius = h * tanTheta;
  glm::vec3 sum(0.0f);
  float coverage = 0.0f;
  float adjacent = h;
  int samples = 0;
  while (samples < maxSamples && coverage < 1.0f) {
    const float radius = adjacent * inRadiusPerHeight;
    const float ratio = radius / footprintRadius;
    const float weight = std::min(ratio * ratio, 1.0f - coverage);
    const glm::vec2 centre = origin + direction * (adjacent - radius);
    sum += weight * SampleCircle(pyramid, centre.x, centre.y, std::max(2.0f * radius, 1.0f));
    coverage += weight;
    adjacent -= 2.0f * radius;
    ++samples;
  }
  return {sum / coverage, samples};
}

const ConeTanTable& SharedConeTanTable() {
  static const ConeTanTable table = BuildConeTanTable();
  return table;
}

}  // namespace

ConeTanTable BuildConeTanTable() {
  ConeTanTable table;
  for (int code = 0; code < 256; ++code) {
    const double roughness = code / 255.0;
    const double alpha = roughness * roughness;
    const double exponent =
        alpha > 0.0 ? std::min(2.0 / (alpha * alpha) - 2.0, kConeMaxPhongExponent) : kConeMaxPhongExponent;
    const double theta = std::acos(std::pow(0.244, 1.0 / (exponent + 1.0)));
    table[size_t(code)] = float(std::tan(theta));
  }
  return table;
}

float ConeHalfAngleTan(uint8_t roughnessCode) { return SharedConeTanTable()[roughnessCode]; }

std::optional<ColorPyramidNeeds> SsrConePyramidNeeds(const Plane<uint32_t>& word1, const Plane<float>& hitX,
                                                    const Plane<float>& hitY, const Plane<float>& confidence,
                                                    const TileMask* tiles, size_t maxRowSpans) {
  const size_t width = confidence.xsize(), height = confidence.ysize();
  const std::vector<PyramidSize> sizes = PyramidLevelSizes(width, height);
  const int lastLevel = int(sizes.size()) - 1;
  ColorPyramidNeeds needs;
  needs.rows.resize(sizes.size());
  for (size_t k = 1; k < sizes.size(); ++k) needs.rows[k].resize(sizes[k].height);
  const ConeTanTable& coneTan = SharedConeTanTable();
  size_t rowSpans = 0;
  // Level k's texels whose bilinear fetches cover level-0 coordinates [lo, hi] along an axis of
  // `size` texels (level 0: `baseSize`), a texel more on each side for the rounding of the circles'
  // centres.
  const auto texels = [](double lo, double hi, size_t size, size_t baseSize, int& first, int& last) {
    const double scale = double(size) / double(baseSize);
    first = std::max(0, int(std::floor(lo * scale - 0.5)) - 1);
    last = std::min(int(size) - 1, int(std::floor(hi * scale - 0.5)) + 2);
  };
  for (size_t y = 0; y < height; ++y) {
    const uint32_t* codes = word1.ConstRow(y);
    const float* hx = hitX.ConstRow(y);
    const float* hy = hitY.ConstRow(y);
    const float* weight = confidence.ConstRow(y);
    bool tooMany = false;
    const auto listRun = [&](int xBegin, int xEnd) {
      for (int x = xBegin; x < xEnd && !tooMany; ++x) {
        const uint32_t code = codes[x] >> 24;
        if (!(weight[x] > 0.0f) || code == 0) continue;  // no hit, or the mirror's level-0 sample
        const double originX = double(x) + 0.5, originY = double(y) + 0.5;
        const double dx = double(hx[x]) - originX, dy = double(hy[x]) - originY;
        const double h = std::sqrt(dx * dx + dy * dy);
        if (h < 0.999 * double(kConeMinHeight)) continue;  // the level-0 sample at the hit
        // The circles' radii are below h tan(theta); SampleCircle reads the level of the diameter
        // and the one above.
        const double diameter = std::max(2.002 * h * double(coneTan[code]), 1.0);
        const int levels = std::min(int(std::floor(std::log2(diameter))) + 1, lastLevel);
        for (int k = 1; k <= levels; ++k) {
          int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
          texels(std::min(originX, double(hx[x])), std::max(originX, double(hx[x])), sizes[size_t(k)].width, width,
                 x0, x1);
          texels(std::min(originY, double(hy[x])), std::max(originY, double(hy[x])), sizes[size_t(k)].height, height,
                 y0, y1);
          for (int row = y0; row <= y1; ++row) needs.rows[size_t(k)][size_t(row)].Add(x0, x1);
          rowSpans += size_t(std::max(0, y1 - y0 + 1));
        }
        tooMany = rowSpans > maxRowSpans;
      }
    };
    ForEachTileRun(tiles, int(y), int(width), listRun, [](int, int) {});
    if (tooMany) return std::nullopt;
  }
  return needs;
}

SsrConeCounts SsrConeRowScalar(const SsrConeContext& context, const uint32_t* word1, const float* hitX,
                               const float* hitY, const float* confidence, size_t y, size_t xBegin, size_t xEnd,
                               float* red, float* green, float* blue) {
  float* rows[3] = {red, green, blue};
  SsrConeCounts counts;
  for (size_t x = xBegin; x < xEnd; ++x) {
    glm::vec3 radiance(0.0f);
    if (confidence[x] > 0.0f) {
      const uint32_t code = word1[x] >> 24;
      const glm::vec2 hit(hitX[x], hitY[x]);
      ConeSample cone{};
      if (code == 0) {
        cone = {SampleLevel(context.pyramid, 0, hit.x, hit.y), 1};  // mirror: the exact hit, no cone
      } else {
        cone = TraceCone(context.pyramid, glm::vec2(float(x) + 0.5f, float(y) + 0.5f), hit, context.coneTan[code],
                         context.maxSamples);
      }
      radiance = cone.radiance;
      counts.samples += size_t(cone.samples);
      ++counts.pixels;
    }
    for (int c = 0; c < 3; ++c) rows[c][x] = radiance[c];
  }
  return counts;
}

SsrConeStats RunSsrCone(const SsrConeInputs& in, const SsrConeParams& params, SsrConeOutputs& out,
                        KernelPath kernels) {
  const Stopwatch stopwatch;
  SSGI_CHECK_GE(params.maxSamples, 1);
  SSGI_CHECK(!in.pyramid.levels.empty());
  const size_t width = size_t(in.gbuffer.width()), height = size_t(in.gbuffer.height());
  SSGI_CHECK_EQ(in.pyramid.levels[0].c[0].xsize(), width);
  SSGI_CHECK_EQ(in.pyramid.levels[0].c[0].ysize(), height);
  SSGI_CHECK_EQ(in.confidence.xsize(), width);
  SSGI_CHECK_EQ(in.confidence.ysize(), height);
  for (Plane<float>& plane : out.reflected.c) {
    if (plane.xsize() != width || plane.ysize() != height) plane = MakePlane<float>(width, height, 0.0f);
  }
  const SsrConeContext context{in.pyramid, SharedConeTanTable(), params.maxSamples};
  SSGI_CHECK(in.tiles == nullptr || in.tiles->Fits(int(width), int(height)));
  std::vector<SsrConeCounts> rowCounts(height);
  ParallelForRowBands("ssr_cone", height, [&](size_t, size_t yBegin, size_t yEnd) {
    if (kernels == KernelPath::kSimd) return SsrConeRowsSimd(context, in, yBegin, yEnd, out, rowCounts.data());
    for (size_t y = yBegin; y < yEnd; ++y) {
      ForEachConeRun(in, y, out, [&](size_t xBegin, size_t xEnd) {
        const SsrConeCounts counts = SsrConeRowScalar(
            context, in.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(y), in.hitX.ConstRow(y),
            in.hitY.ConstRow(y), in.confidence.ConstRow(y), y, xBegin, xEnd, out.reflected.c[0].MutableRow(y),
            out.reflected.c[1].MutableRow(y), out.reflected.c[2].MutableRow(y));
        rowCounts[y].samples += counts.samples;
        rowCounts[y].pixels += counts.pixels;
      });
    }
  });
  SsrConeStats stats;
  for (const SsrConeCounts& counts : rowCounts) {
    stats.samples += counts.samples;
    stats.pixels += counts.pixels;
  }
  stats.ms = stopwatch.Milliseconds();
  return stats;
}

}  // namespace ssgi
