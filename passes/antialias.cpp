#include "passes/antialias.h"

#include <algorithm>
#include <vector>

#include "core/check.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi {

namespace {

// One blended pixel, written after every band has read its neighbours.
struct BlendedPixel {
  uint32_t x, y;
  float rgb[3];
};

}  // namespace

void AntialiasRowScalar(const uint32_t* coverage, const float* const rows[3][3], size_t width,
                        float* const blended[3]) {
  AntialiasPixelsScalar(coverage, rows, width, 0, width, blended);
}

void AntialiasPixelsScalar(const uint32_t* coverage, const float* const rows[3][3], size_t width, size_t begin,
                           size_t end, float* const blended[3]) {
  for (size_t x = begin; x < end; ++x) {
    const uint32_t word = coverage[x];
    if (word == 0) continue;
    const float wl = float(word & 255u), wr = float((word >> 8) & 255u), wu = float((word >> 16) & 255u),
                wd = float(word >> 24);
    const float w0 = float(256u - (word & 255u) - ((word >> 8) & 255u) - ((word >> 16) & 255u) - (word >> 24));
    const size_t left = x > 0 ? x - 1 : x, right = x + 1 < width ? x + 1 : x;
    for (int c = 0; c < 3; ++c) {
      const float* row = rows[c][1];
      float sum = row[x] * w0;
      sum = sum + row[left] * wl;
      sum = sum + row[right] * wr;
      sum = sum + rows[c][0][x] * wu;
      sum = sum + rows[c][2][x] * wd;
      blended[c][x] = sum * (1.0f / 256.0f);
    }
  }
}

AntialiasStats RunAntialias(const AntialiasInputs& in, Plane3<float>& out, KernelPath kernels) {
  Stopwatch stopwatch;
  const size_t width = in.image.c[0].xsize(), height = in.image.c[0].ysize();
  SSGI_CHECK_EQ(in.edgeCoverage.xsize(), width);
  SSGI_CHECK_EQ(in.edgeCoverage.ysize(), height);
  const bool inPlace = &out == &in.image;
  if (!inPlace && (out.c[0].xsize() != width || out.c[0].ysize() != height))
    out = MakePlane3<float>(width, height, 0.0f);
  const auto rowKernel = kernels == KernelPath::kSimd ? AntialiasRowSimd : AntialiasRowScalar;
  // Each band blends its rows into a scratch row and keeps the blended pixels; they are written
  // once every band has read the image.
  std::vector<std::vector<BlendedPixel>> blendedPerBand(RowBandCount(height));
  ParallelForRowBands("antialias", height, [&](size_t band, size_t yBegin, size_t yEnd) {
    std::vector<float> scratch(3 * width);
    float* const blended[3] = {scratch.data(), scratch.data() + width, scratch.data() + 2 * width};
    std::vector<BlendedPixel>& list = blendedPerBand[band];
    for (size_t y = yBegin; y < yEnd; ++y) {
      const uint32_t* coverage = in.edgeCoverage.ConstRow(y);
      if (!inPlace)
        for (int c = 0; c < 3; ++c) std::copy_n(in.image.c[c].ConstRow(y), width, out.c[c].MutableRow(y));
      const size_t up = y > 0 ? y - 1 : y, down = y + 1 < height ? y + 1 : y;
      const float* const rows[3][3] = {
          {in.image.c[0].ConstRow(up), in.image.c[0].ConstRow(y), in.image.c[0].ConstRow(down)},
          {in.image.c[1].ConstRow(up), in.image.c[1].ConstRow(y), in.image.c[1].ConstRow(down)},
          {in.image.c[2].ConstRow(up), in.image.c[2].ConstRow(y), in.image.c[2].ConstRow(down)}};
      rowKernel(coverage, rows, width, blended);
      for (size_t x = 0; x < width; ++x)
        if (coverage[x] != 0) list.push_back({uint32_t(x), uint32_t(y), {blended[0][x], blended[1][x], blended[2][x]}});
    }
  });
  AntialiasStats stats;
  ParallelFor("antialias.write", blendedPerBand.size(), [&](size_t band) {
    for (const BlendedPixel& p : blendedPerBand[band])
      for (int c = 0; c < 3; ++c) out.c[c].MutableRow(p.y)[p.x] = p.rgb[c];
  });
  for (const std::vector<BlendedPixel>& list : blendedPerBand) stats.edgePixels += list.size();
  stats.ms = stopwatch.Lap();
  return stats;
}

}  // namespace ssgi
