// SSR Hi-Z trace: driver and scalar row kernel (docs/pipeline.md §SSR: Hi-Z trace).
#include "passes/ssr_trace.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/check.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi {
namespace {

float SafeReciprocal(float v) { return std::fabs(v) < kHiZTinyComponent ? kHiZNever : 1.0f / v; }

// The cell of level-0 coordinate p at a level with `size` cells of 2^level pixels; the last cell
// also covers the remainder of a floor-halved size (PyramidFootprintEnd).
int CellIndex(float p, int level, int size) {
  const int pixel = int(std::clamp(p, 0.0f, kHiZMaxCoordinate));
  return std::min(pixel >> level, size - 1);
}

// The boundary of cell `cell` the ray leaves through: the upper one for positive (and zero)
// direction, the lower one for negative; the last cell's upper boundary is the image border.
float CellBoundary(int cell, int level, int size, int imageSize, bool positive) {
  if (!positive) return float(cell << level);
  return cell + 1 == size ? float(imageSize) : float((cell + 1) << level);
}

bool InsideImage(glm::vec3 p, float width, float height) {
  return p.x >= 0.0f && p.x < width && p.y >= 0.0f && p.y < height;
}

// One pixel's outputs; the defaults are those of untraced pixels, misses and rejected hits.
struct PixelHit {
  float x = -1.0f;
  float y = -1.0f;
  float confidence = 0.0f;
  float iterations = 0.0f;
};

class PixelTracer {
 public:
  PixelTracer(const SsrTraceInputs& in, const SsrTraceParams& params)
      : in_(in), params_(params), width_(float(in.gbuffer.width())), height_(float(in.gbuffer.height())) {}

  // Traces pixel (x, y) when it has geometry below the roughness cut-off; counts traced rays.
  PixelHit Trace(int x, int y, SsrTraceCounts& counts) const {
    PixelHit none;
    const float d = UnpackDepth(in_.gbuffer.word[GBufferWord::kDepth].ConstRow(size_t(y))[x]);
    if (!(d < kBackgroundDepth) || !(d > 0.0f)) return none;
    const uint32_t word1 = in_.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(size_t(y))[x];
    if (!(UnpackRoughness(word1) < params_.roughnessCutoff)) return none;

    const glm::vec3 p = in_.view.PixelRay(float(x) + 0.5f, float(y) + 0.5f).direction * d;
    const glm::vec3 n = UnpackNormal(word1, in_.gbuffer.normalEncoding);
    const glm::vec3 v = p / std::sqrt(glm::dot(p, p));
    const glm::vec3 r = v - 2.0f * glm::dot(v, n) * n;
    // Rays toward the camera: the max pyramid has no back side, so fade them (see the header).
    const float towardCamera = r.z <= 0.0f ? 1.0f : 1.0f - r.z / params_.towardCameraFade;
    if (!(towardCamera > 0.0f)) return none;

    // Near-plane clip before projecting: the end's view depth d - r.z L stays >= near.
    float length = kSsrMaxRayLengthInDepths * d;
    if (r.z > 0.0f) length = std::min(length, (d - in_.view.nearPlane) / r.z);
    if (!(length > 0.0f)) return none;
    const glm::vec3 q = p + r * length;
    if (!(-q.z > 0.0f)) return none;

    ++counts.rays;
    const HiZRay ray{{float(x) + 0.5f, float(y) + 0.5f, 1.0f / d}, Project(q)};
    const HiZMarch march = MarchHiZ(in_.hiz, ray, params_.maxIterations, params_.startLevel);
    counts.iterations += uint64_t(march.iterations);
    PixelHit miss;
    miss.iterations = float(march.iterations);
    if (!march.hit || !InsideImage(march.position, width_, height_) || !(march.position.z > 0.0f))
      return miss;

    const int hx = std::min(int(march.position.x), in_.gbuffer.width() - 1);
    const int hy = std::min(int(march.position.y), in_.gbuffer.height() - 1);
    const float hitDepth = UnpackDepth(in_.gbuffer.word[GBufferWord::kDepth].ConstRow(size_t(hy))[hx]);
    if (!(hitDepth < kBackgroundDepth)) return miss;
    const glm::vec3 hitNormal = UnpackNormal(in_.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(size_t(hy))[hx],
                                             in_.gbuffer.normalEncoding);
    // Back faces and surfaces the ray only grazes cannot reflect light back along r.
    if (glm::dot(hitNormal, r) >= 0.0f) return miss;

    // Relative depth excess of the ray over the surface: (ray d - surface d) / surface d.
    const float excess = (1.0f / march.position.z) / hitDepth - 1.0f;
    const float thickness = std::clamp(2.0f - excess / params_.thickness, 0.0f, 1.0f);
    const float confidence = thickness * towardCamera * EdgeFade(march.position.x, width_) *
                             EdgeFade(march.position.y, height_);
    if (!(confidence > 0.0f)) return miss;
    return {march.position.x, march.position.y, std::min(confidence, 1.0f), miss.iterations};
  }

 private:
  // View-space point (in front of the camera) -> (x, y, 1/d), docs/pipeline.md §Conventions.
  glm::vec3 Project(glm::vec3 q) const {
    const float depth = -q.z;
    const float ndcX = q.x / (depth * in_.view.halfX);
    const float ndcY = q.y / (depth * in_.view.halfY);
    return {(ndcX * 0.5f + 0.5f) * width_, (0.5f - ndcY * 0.5f) * height_, 1.0f / depth};
  }

  float EdgeFade(float p, float size) const {
    if (!(params_.edgeFade > 0.0f)) return 1.0f;
    return std::clamp(std::min(p, size - p) / (params_.edgeFade * size), 0.0f, 1.0f);
  }

  const SsrTraceInputs& in_;
  const SsrTraceParams& params_;
  float width_;
  float height_;
};

void ShapeOutput(Plane<float>& plane, size_t width, size_t height) {
  if (plane.xsize() != width || plane.ysize() != height) plane = MakePlane<float>(width, height, 0.0f);
}

bool NormalCodesClose(uint32_t a, uint32_t b, NormalEncoding encoding) {
  const bool xyz8 = encoding == NormalEncoding::kXyz8;
  const int fields = xyz8 ? 3 : 2, bits = xyz8 ? 8 : 12;
  const uint32_t mask = (1u << bits) - 1u;
  const int32_t steps = xyz8 ? kSharedRayOctStepsXyz8 : kSharedRayOctStepsOct24;
  for (int k = 0; k < fields; ++k) {
    const int32_t difference = int32_t((a >> (k * bits)) & mask) - int32_t((b >> (k * bits)) & mask);
    if (std::abs(difference) > steps) return false;
  }
  return true;
}

}  // namespace

HiZMarch MarchHiZ(const HiZ& hiz, const HiZRay& ray, int maxIterations, int startLevel) {
  SSGI_CHECK(!hiz.levels.empty());
  SSGI_CHECK_GE(startLevel, 0);
  HiZMarch result;
  const int imageWidth = int(hiz.levels[0].xsize());
  const int imageHeight = int(hiz.levels[0].ysize());
  const float width = float(imageWidth);
  const float height = float(imageHeight);
  const int topLevel = int(hiz.levels.size()) - 1;
  if (!std::isfinite(ray.origin.x) || !std::isfinite(ray.origin.y) || !std::isfinite(ray.origin.z) ||
      !std::isfinite(ray.end.x) || !std::isfinite(ray.end.y) || !std::isfinite(ray.end.z) ||
      !InsideImage(ray.origin, width, height))
    return result;

  // Snap the origin strictly inside its level-0 cell, so its first boundary crossing leaves that
  // cell and no rounding can put it on the far side of a boundary it has not crossed.
  glm::vec3 pos = ray.origin;
  const int startX = CellIndex(pos.x, 0, imageWidth);
  const int startY = CellIndex(pos.y, 0, imageHeight);
  pos.x = std::clamp(pos.x, float(startX) + kHiZBoundaryNudge, float(startX + 1) - kHiZBoundaryNudge);
  pos.y = std::clamp(pos.y, float(startY) + kHiZBoundaryNudge, float(startY + 1) - kHiZBoundaryNudge);
  result.position = pos;

  const glm::vec3 dir = ray.end - pos;
  const glm::vec3 inv{SafeReciprocal(dir.x), SafeReciprocal(dir.y), SafeReciprocal(dir.z)};
  const bool positiveX = !(dir.x <= -kHiZTinyComponent);
  const bool positiveY = !(dir.y <= -kHiZTinyComponent);
  // The march ends at the segment's end or where it leaves the image, whichever comes first.
  const float exitX = ((positiveX ? width : 0.0f) - pos.x) * inv.x;
  const float exitY = ((positiveY ? height : 0.0f) - pos.y) * inv.y;
  const float tEnd = std::min({1.0f, exitX, exitY});

  float t = 0.0f;
  int level = 0;
  bool skipOrigin = true;  // the first step leaves the origin's own cell: it holds the reflector
  while (result.iterations < maxIterations) {
    ++result.iterations;
    const Plane<float>& plane = hiz.levels[size_t(level)];
    const int sizeX = int(plane.xsize());
    const int sizeY = int(plane.ysize());
    const int cellX = CellIndex(pos.x, level, sizeX);
    const int cellY = CellIndex(pos.y, level, sizeY);
    const float closest = plane.ConstRow(size_t(cellY))[cellX];

    // Un-offset cell planes: the nudge below is what moves the ray across, on one axis only, so an
    // axis-aligned ray (the other axis' t is kHiZNever) can never stall on a boundary.
    const float boundaryX = CellBoundary(cellX, level, sizeX, imageWidth, positiveX);
    const float boundaryY = CellBoundary(cellY, level, sizeY, imageHeight, positiveY);
    const float tX = (boundaryX - pos.x) * inv.x;
    const float tY = (boundaryY - pos.y) * inv.y;
    const float tCell = std::min(tX, tY);
    // The ray meets the cell's closest-depth plane: now if it is already at or behind it, ahead if
    // it recedes (1/d falling), never if it approaches the camera in front of it.
    float tDepth = kHiZNever;
    if (!skipOrigin) {
      if (pos.z <= closest) tDepth = 0.0f;
      else if (dir.z <= -kHiZTinyComponent) tDepth = (closest - pos.z) * inv.z;
    }
    skipOrigin = false;

    if (tDepth < tCell) {
      if (t + tDepth > tEnd) return result;
      pos += dir * tDepth;
      t += tDepth;
      result.position = pos;
      if (level == 0) {
        result.hit = true;
        return result;
      }
      --level;
    } else {
      if (t + tCell >= tEnd) return result;
      pos += dir * tCell;
      t += tCell;
      if (tX <= tY) pos.x = boundaryX + (positiveX ? kHiZBoundaryNudge : -kHiZBoundaryNudge);
      else pos.y = boundaryY + (positiveY ? kHiZBoundaryNudge : -kHiZBoundaryNudge);
      result.position = pos;
      if (!InsideImage(pos, width, height)) return result;
      level = std::min(result.iterations == 1 ? startLevel : level + 1, topLevel);
    }
  }
  return result;
}

SsrRaySource SsrRaySourceOf(const SsrTraceInputs& in, const SsrTraceParams& params, int x, int y) {
  const GBuffer& g = in.gbuffer;
  const auto word1 = [&](int px, int py) { return g.word[GBufferWord::kNormalRoughness].ConstRow(size_t(py))[px]; };
  const auto depth = [&](int px, int py) { return UnpackDepth(g.word[GBufferWord::kDepth].ConstRow(size_t(py))[px]); };
  const auto traces = [&](uint32_t w1, float d) {
    return d < kBackgroundDepth && d > 0.0f && UnpackRoughness(w1) < params.roughnessCutoff;
  };
  const uint32_t ownWord = word1(x, y);
  const float ownDepth = depth(x, y);
  if (!traces(ownWord, ownDepth)) return SsrRaySource::kOwn;
  const auto shares = [&](int mask, float threshold) {
    const int sx = x & mask, sy = y & mask;
    if (sx == x && sy == y) return false;
    const uint32_t sourceWord = word1(sx, sy);
    const float sourceDepth = depth(sx, sy);
    return traces(sourceWord, sourceDepth) && UnpackRoughness(ownWord) >= threshold &&
           UnpackRoughness(sourceWord) >= threshold &&
           std::fabs(ownDepth - sourceDepth) <= kSharedRayDepthTolerance * sourceDepth &&
           NormalCodesClose(ownWord, sourceWord, g.normalEncoding);
  };
  if (shares(~3, params.blockRoughness)) return SsrRaySource::kBlock;
  if (shares(~1, params.quadRoughness)) return SsrRaySource::kQuad;
  return SsrRaySource::kOwn;
}

namespace {

// The kernel's last step: each pixel whose source (sources[] row by row over the tile) is not its
// own gets its source's hit and confidence, and 0 steps.
void CopySharedHits(const SsrTraceTile& tile, const SsrRaySource* sources, SsrTraceOutputs& out) {
  const int width = tile.x1 - tile.x0;
  // Blocks first: a quad's top-left pixel may itself take its block's ray.
  for (const SsrRaySource shared : {SsrRaySource::kBlock, SsrRaySource::kQuad}) {
    const int mask = shared == SsrRaySource::kBlock ? ~3 : ~1;
    for (int y = tile.y0; y < tile.y1; ++y) {
      float* iterations = IterationsRow(out, y);
      for (int x = tile.x0; x < tile.x1; ++x) {
        if (sources[size_t(y - tile.y0) * size_t(width) + size_t(x - tile.x0)] != shared) continue;
        const size_t sx = size_t(x & mask), sy = size_t(y & mask);
        out.hitX.MutableRow(size_t(y))[x] = out.hitX.ConstRow(sy)[sx];
        out.hitY.MutableRow(size_t(y))[x] = out.hitY.ConstRow(sy)[sx];
        out.confidence.MutableRow(size_t(y))[x] = out.confidence.ConstRow(sy)[sx];
        if (iterations) iterations[x] = 0.0f;
      }
    }
  }
}

}  // namespace

void SsrTraceTileScalar(const SsrTraceInputs& in, const SsrTraceParams& params, const SsrTraceTile& tile,
                        SsrTraceOutputs& out, SsrTraceCounts& counts) {
  SSGI_CHECK(tile.x0 % 4 == 0 && tile.y0 % 4 == 0);
  const PixelTracer tracer(in, params);
  const int width = tile.x1 - tile.x0;
  std::vector<SsrRaySource> sources(size_t(width) * size_t(tile.y1 - tile.y0));
  const auto source = [&](int x, int y) -> SsrRaySource& {
    return sources[size_t(y - tile.y0) * size_t(width) + size_t(x - tile.x0)];
  };
  for (int y = tile.y0; y < tile.y1; ++y) {
    for (int x = tile.x0; x < tile.x1; ++x) {
      source(x, y) = SsrRaySourceOf(in, params, x, y);
      if (source(x, y) != SsrRaySource::kOwn) continue;
      const PixelHit hit = tracer.Trace(x, y, counts);
      out.hitX.MutableRow(size_t(y))[x] = hit.x;
      out.hitY.MutableRow(size_t(y))[x] = hit.y;
      out.confidence.MutableRow(size_t(y))[x] = hit.confidence;
      if (float* iterations = IterationsRow(out, y)) iterations[x] = hit.iterations;
    }
  }
  CopySharedHits(tile, sources.data(), out);
}

SsrTraceStats RunSsrTrace(const SsrTraceInputs& in, const SsrTraceParams& params, SsrTraceOutputs& out,
                          KernelPath kernels, SsrTraceSteps steps) {
  const Stopwatch stopwatch;
  const int width = in.gbuffer.width();
  const int height = in.gbuffer.height();
  SSGI_CHECK(!in.view.orthographic);
  SSGI_CHECK_EQ(in.view.width, width);
  SSGI_CHECK_EQ(in.view.height, height);
  SSGI_CHECK(!in.hiz.levels.empty());
  SSGI_CHECK_EQ(in.hiz.levels[0].xsize(), size_t(width));
  SSGI_CHECK_EQ(in.hiz.levels[0].ysize(), size_t(height));
  SSGI_CHECK_GE(params.maxIterations, 1);
  SSGI_CHECK_GE(params.startLevel, 0);
  SSGI_CHECK_GT(params.thickness, 0.0f);
  SSGI_CHECK_GT(params.towardCameraFade, 0.0f);
  ShapeOutput(out.hitX, size_t(width), size_t(height));
  ShapeOutput(out.hitY, size_t(width), size_t(height));
  ShapeOutput(out.confidence, size_t(width), size_t(height));
  if (steps == SsrTraceSteps::kRecord) ShapeOutput(out.iterations, size_t(width), size_t(height));
  else out.iterations = Plane<float>();

  const int tilesX = (width + kSsrTraceTileSize - 1) / kSsrTraceTileSize;
  const int tilesY = (height + kSsrTraceTileSize - 1) / kSsrTraceTileSize;
  SSGI_CHECK(in.tiles == nullptr || in.tiles->Fits(width, height));
  std::vector<SsrTraceCounts> counts(size_t(tilesX) * size_t(tilesY));
  // Tiles the mask leaves out hold no pixel that traces: "no hit" is stored there unread, a row's
  // run of such tiles at a time (long runs stream; a 32-pixel piece per row of a tile does not).
  std::vector<size_t> traced;
  for (size_t tile = 0; tile < counts.size(); ++tile) {
    if (in.tiles == nullptr || in.tiles->needed[tile]) traced.push_back(tile);
  }
  if (traced.size() < counts.size() && !in.leaveSkippedTiles) {
    ParallelForRowBands("ssr_trace.no_hits", size_t(height), [&](size_t, size_t yBegin, size_t yEnd) {
      for (size_t y = yBegin; y < yEnd; ++y) {
        ForEachTileRun(in.tiles, int(y), width, [](int, int) {}, [&](int x0, int x1) {
          std::fill(out.hitX.MutableRow(y) + x0, out.hitX.MutableRow(y) + x1, -1.0f);
          std::fill(out.hitY.MutableRow(y) + x0, out.hitY.MutableRow(y) + x1, -1.0f);
          std::fill(out.confidence.MutableRow(y) + x0, out.confidence.MutableRow(y) + x1, 0.0f);
          if (float* iterations = IterationsRow(out, int(y))) std::fill(iterations + x0, iterations + x1, 0.0f);
        });
      }
    });
  }
  ParallelFor("ssr_trace", traced.size(), [&](size_t i) {
    const size_t tile = traced[i];
    const int x0 = int(tile % size_t(tilesX)) * kSsrTraceTileSize;
    const int y0 = int(tile / size_t(tilesX)) * kSsrTraceTileSize;
    const int x1 = std::min(x0 + kSsrTraceTileSize, width);
    const int y1 = std::min(y0 + kSsrTraceTileSize, height);
    const auto kernel = kernels == KernelPath::kSimd ? SsrTraceTileSimd : SsrTraceTileScalar;
    kernel(in, params, {x0, y0, x1, y1}, out, counts[tile]);
  });

  SsrTraceStats stats;
  stats.tiles = counts.size();
  uint64_t iterations = 0;
  for (const SsrTraceCounts& tile : counts) {
    stats.rays += tile.rays;
    iterations += tile.iterations;
    if (tile.rays > 0) ++stats.tilesTraced;
  }
  stats.meanIterations = stats.rays > 0 ? double(iterations) / double(stats.rays) : 0.0;
  stats.ms = stopwatch.Milliseconds();
  return stats;
}

}  // namespace ssgi
