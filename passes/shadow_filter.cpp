// Screen-space soft-shadow filter: driver and scalar kernels (docs/pipeline.md §Shadow filter).
#include "passes/shadow_filter.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/check.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi {
namespace {

// Bilateral acceptance of a tap (docs/pipeline.md §Shadow filter): the tap's normal within about 37
// degrees of the centre's, and the tap's point within 2 % of the centre's view depth of the centre's
// tangent plane. The plane distance, unlike a raw depth difference, does not reject taps on the
// centre's own surface seen at a grazing angle, where depth changes quickly from pixel to pixel.
constexpr float kMinNormalDot = 0.8f;
constexpr float kMaxPlaneDistance = 0.02f;
// A projected normal shorter than this faces the camera: the ellipse's axes are undefined, so the
// kernel falls back to a circle with a screen-x major axis (Zheng & Saito's known degenerate case).
constexpr float kMinProjectedNormal = 1e-4f;
// Metres; keeps the spot light's PCSS denominator (light-to-blocker distance) away from 0.
constexpr float kMinLightToBlocker = 1e-3f;
// Kernels shorter than this (pixels) leave the hard value (a pixel's own tap only).
constexpr float kMinBlurRadius = 0.5f;

// PCSS penumbra half-width in pixels (Fernando 2005, eq. 1, with the blocker distance d_b measured
// from the receiver): w = d_b * lightSize / (distance from the blocker to the light), projected with
// the receiver's pixels per metre and clamped. Non-finite products (0 * inf) mean no blur.
float PenumbraRadiusPixels(const PreparedLight& light, const ShadowFilterTexel& c, float blockerDistance,
                           float pixelsPerMetre, float maxRadius) {
  float width;
  if (light.isSpot) {
    const float toLight = glm::length(light.position - c.position);
    width = blockerDistance * 2.0f * light.radius / std::max(toLight - blockerDistance, kMinLightToBlocker);
  } else {
    width = blockerDistance * 2.0f * light.tanAngularRadius;
  }
  const float radius = 0.5f * width * pixelsPerMetre;
  if (!(radius > 0.0f)) return 0.0f;
  return std::min(radius, maxRadius);
}

// The kernel of a pixel with penumbra half-width `radius`. SSABSS (Zheng & Saito): the screen image
// of the receiver's normal gives the minor axis, foreshortened by the TRUE |n . v| (v the unit vector
// to the camera; n.z alone is wrong away from the image centre); the major axis is perpendicular.
ShadowFilterKernel MakeKernel(ShadowFilter filter, const ShadowFilterTexel& c, float radius) {
  if (filter == ShadowFilter::kHard || radius < kMinBlurRadius) return {};
  if (filter == ShadowFilter::kSspcss) return {{1.0f, 0.0f}, radius, radius};
  const glm::vec3& p = c.position;
  const glm::vec3& n = c.normal;
  const float depth = -p.z;
  // Derivative of the perspective projection (x / d, -y / d) at p along n, times d.
  const glm::vec2 projected(n.x + p.x / depth * n.z, -(n.y + p.y / depth * n.z));
  const float length = std::sqrt(glm::dot(projected, projected));
  if (length < kMinProjectedNormal) return {{1.0f, 0.0f}, radius, radius};
  const glm::vec2 m = projected / length;
  const float facing = std::fabs(glm::dot(n, -p)) / std::sqrt(glm::dot(p, p));
  return {{m.y, -m.x}, radius, radius * facing};
}

bool Accepts(const ShadowFilterTexel& c, const ShadowFilterTexel& tap) {
  return tap.geometry && glm::dot(tap.normal, c.normal) > kMinNormalDot &&
         std::fabs(glm::dot(c.normal, tap.position - c.position)) < kMaxPlaneDistance * -c.position.z;
}

struct Frame {
  int width = 0, height = 0;
  std::vector<ShadowFilterTexel> texels;
  std::vector<ShadowFilterKernel> kernels;
  std::vector<float> hard;  // 0 shadowed, 1 lit; background 1
};

// One 1-D pass at pixel (x, y): a box of half-length `length` pixels along `direction`, sampled with
// nearest-pixel taps, bilateral, centre weight 1. taps = 0: taps at unit spacing, the last one
// weighted by the fraction of its pixel the box covers (a box filter of exact width, so a straight
// edge becomes a linear ramp of width 2 * length); taps > 0: that many equal taps per side at
// spacing length / (taps + 0.5), each standing for the same share of the box. Summed in a fixed
// order: offsets outward, negative side first.
float Blur1D(const ShadowFilterImage& f, const float* value, int x, int y, glm::vec2 direction, float length,
             int taps) {
  const size_t centre = size_t(y) * size_t(f.width) + size_t(x);
  const ShadowFilterTexel& c = f.texels[centre];
  if (!c.geometry || length < kMinBlurRadius) return value[centre];
  const int count = taps > 0 ? taps : int(std::ceil(length - 0.5f));
  const float spacing = taps > 0 ? length / (float(taps) + 0.5f) : 1.0f;
  float sum = value[centre], weightSum = 1.0f;
  for (int k = 1; k <= count; ++k) {
    const float t = float(k) * spacing;
    const float weight = taps > 0 ? 1.0f : std::min(1.0f, length - (t - 0.5f));
    for (const float side : {-1.0f, 1.0f}) {
      const float sx = std::floor(float(x) + 0.5f + side * t * direction.x);
      const float sy = std::floor(float(y) + 0.5f + side * t * direction.y);
      if (sx < 0.0f || sy < 0.0f || sx >= float(f.width) || sy >= float(f.height)) continue;
      const size_t tap = size_t(sy) * size_t(f.width) + size_t(sx);
      if (!Accepts(c, f.texels[tap])) continue;
      sum += weight * value[tap];
      weightSum += weight;
    }
  }
  return sum / weightSum;
}

// Pixels [x0, x1) x [y0, y1) of tile `tile` (row-major tiles of kShadowFilterTileSize).
struct TileRect {
  int x0, y0, x1, y1;
};
TileRect TileBounds(const Frame& f, int tilesX, size_t tile) {
  const int x0 = int(tile % size_t(tilesX)) * kShadowFilterTileSize;
  const int y0 = int(tile / size_t(tilesX)) * kShadowFilterTileSize;
  return {x0, y0, std::min(f.width, x0 + kShadowFilterTileSize), std::min(f.height, y0 + kShadowFilterTileSize)};
}

// Calls body(x, y) for every pixel of tile `tile`.
template <class Body>
void ForTilePixels(const Frame& f, int tilesX, size_t tile, Body&& body) {
  const TileRect r = TileBounds(f, tilesX, tile);
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x) body(x, y);
}

// A skipped tile's row: the hard value, which is what the blur would give there.
void CopyHardRow(const Frame& f, int y, int x0, int x1, float* out) {
  const float* hard = f.hard.data() + size_t(y) * size_t(f.width);
  std::copy(hard + x0, hard + x1, out + x0);
}

ShadowFilterStats Run(const ShadowFilterInputs& in, const ShadowFilterParams& params, bool skipTiles,
                      ShadowFilterOutputs& out) {
  SSGI_CHECK(params.maxRadiusPixels >= 0);
  SSGI_CHECK(params.taps >= 0);
  SSGI_CHECK(!in.view.orthographic);
  const Stopwatch watch;
  Frame f;
  f.width = in.gbuffer.width();
  f.height = in.gbuffer.height();
  const size_t pixelCount = size_t(f.width) * size_t(f.height);
  f.texels.resize(pixelCount);
  f.kernels.resize(pixelCount);
  f.hard.resize(pixelCount);
  if (out.visibility.xsize() != size_t(f.width) || out.visibility.ysize() != size_t(f.height))
    out.visibility = MakePlane<float>(size_t(f.width), size_t(f.height), 1.0f);

  const float maxRadius = float(params.maxRadiusPixels);
  const float pixelsPerMetreAtUnitDepth = float(f.height) / (2.0f * in.view.halfY);
  const ShadowFilterSetupContext setup{in.view, in.light, in.gbuffer.normalEncoding, params.filter, maxRadius,
                                       pixelsPerMetreAtUnitDepth};
  const int bands = (f.height + kShadowFilterTileSize - 1) / kShadowFilterTileSize;
  ParallelFor("shadow_filter.setup", size_t(bands), [&](size_t band) {
    const int y0 = int(band) * kShadowFilterTileSize;
    const int y1 = std::min(f.height, y0 + kShadowFilterTileSize);
    for (int y = y0; y < y1; ++y) {
      const size_t row = size_t(y) * size_t(f.width);
      ShadowFilterSetupRowScalar(setup, in.gbuffer.word[1].ConstRow(size_t(y)), in.gbuffer.word[2].ConstRow(size_t(y)),
                                 in.gbuffer.word[3].ConstRow(size_t(y)), y, f.width, f.texels.data() + row,
                                 f.kernels.data() + row, f.hard.data() + row);
    }
  });

  // Blur-area control (DESIGN.md §5, §9). A tile is skipped, its output the hard value, when
  // (a) no pixel of it has a kernel (each output uses only its own kernel in the second pass and its
  // own tap in the first), or (b) every pixel within the two passes' reach (2 * maxRadius, rounded
  // up to whole tiles) is shadowed or background: every accepted tap is then 0, and so is the blur.
  // Both give the blur's exact bits, so skipping never changes the image.
  const int tilesX = (f.width + kShadowFilterTileSize - 1) / kShadowFilterTileSize;
  const int tilesY = bands;
  const size_t tileCount = size_t(tilesX) * size_t(tilesY);
  std::vector<char> hasKernel(tileCount), allDark(tileCount), blurred(tileCount);
  std::vector<size_t> geometryPixels(tileCount);
  ParallelFor("shadow_filter.classify", tileCount, [&](size_t tile) {
    bool kernel = false, dark = true;
    size_t geometry = 0;
    ForTilePixels(f, tilesX, tile, [&](int x, int y) {
      const size_t i = size_t(y) * size_t(f.width) + size_t(x);
      kernel = kernel || f.kernels[i].majorLength >= kMinBlurRadius;
      dark = dark && (!f.texels[i].geometry || f.hard[i] == 0.0f);
      geometry += f.texels[i].geometry;
    });
    hasKernel[tile] = kernel;
    allDark[tile] = dark;
    geometryPixels[tile] = geometry;
  });
  const int reach = (2 * params.maxRadiusPixels + kShadowFilterTileSize - 1) / kShadowFilterTileSize;
  ShadowFilterStats stats;
  stats.tiles = tileCount;
  for (size_t tile = 0; tile < tileCount; ++tile) {
    const int tx = int(tile % size_t(tilesX)), ty = int(tile / size_t(tilesX));
    bool darkAround = true;
    for (int y = std::max(0, ty - reach); y <= std::min(tilesY - 1, ty + reach) && darkAround; ++y)
      for (int x = std::max(0, tx - reach); x <= std::min(tilesX - 1, tx + reach); ++x)
        darkAround = darkAround && allDark[size_t(y) * size_t(tilesX) + size_t(x)];
    blurred[tile] = !skipTiles || (hasKernel[tile] && !darkAround);
    if (blurred[tile]) {
      ++stats.tilesBlurred;
      stats.pixels += geometryPixels[tile];
    }
  }

  // Pass 1 along each pixel's major axis, pass 2 along the minor axis of the output pixel; the
  // intermediate of a skipped tile is its hard value, which is what the blur would give there.
  const ShadowFilterImage image{f.texels.data(), f.kernels.data(), f.width, f.height};
  std::vector<float> majorPass(pixelCount);
  ParallelFor("shadow_filter.major", tileCount, [&](size_t tile) {
    const TileRect r = TileBounds(f, tilesX, tile);
    for (int y = r.y0; y < r.y1; ++y) {
      float* row = majorPass.data() + size_t(y) * size_t(f.width);
      if (blurred[tile]) {
        ShadowFilterMajorRowScalar(image, f.hard.data(), params.taps, y, r.x0, r.x1, row);
      } else {
        CopyHardRow(f, y, r.x0, r.x1, row);
      }
    }
  });
  ParallelFor("shadow_filter.minor", tileCount, [&](size_t tile) {
    const TileRect r = TileBounds(f, tilesX, tile);
    for (int y = r.y0; y < r.y1; ++y) {
      float* row = out.visibility.MutableRow(size_t(y));
      if (blurred[tile]) {
        ShadowFilterMinorRowScalar(image, majorPass.data(), params.taps, y, r.x0, r.x1, row);
      } else {
        CopyHardRow(f, y, r.x0, r.x1, row);
      }
    }
  });
  stats.ms = watch.Milliseconds();
  return stats;
}

}  // namespace

void ShadowFilterSetupRowScalar(const ShadowFilterSetupContext& context, const uint32_t* word1, const uint32_t* word2,
                                const uint32_t* word3, int y, int width, ShadowFilterTexel* texels,
                                ShadowFilterKernel* kernels, float* hard) {
  for (int x = 0; x < width; ++x) {
    const float depth = UnpackDepth(word2[x]);
    if (!(depth > 0.0f && depth < kBackgroundDepth)) {
      texels[x] = {};
      kernels[x] = {};
      hard[x] = 1.0f;
      continue;
    }
    ShadowFilterTexel& t = texels[x];
    t.position = depth * context.view.PixelRay(float(x) + 0.5f, float(y) + 0.5f).direction;
    t.normal = UnpackNormal(word1[x], context.normalEncoding);
    t.geometry = true;
    hard[x] = UnpackHardShadow(word3[x]) ? 0.0f : 1.0f;
    const float radius = PenumbraRadiusPixels(context.light, t, UnpackBlockerDistance(word3[x]),
                                              context.pixelsPerMetreAtUnitDepth / depth, context.maxRadius);
    kernels[x] = MakeKernel(context.filter, t, radius);
  }
}

void ShadowFilterMajorRowScalar(const ShadowFilterImage& image, const float* hard, int taps, int y, int xBegin,
                                int xEnd, float* majorPass) {
  const ShadowFilterKernel* kernels = image.kernels + size_t(y) * size_t(image.width);
  for (int x = xBegin; x < xEnd; ++x)
    majorPass[x] = Blur1D(image, hard, x, y, kernels[x].major, kernels[x].majorLength, taps);
}

void ShadowFilterMinorRowScalar(const ShadowFilterImage& image, const float* majorPass, int taps, int y, int xBegin,
                                int xEnd, float* visibility) {
  const ShadowFilterKernel* kernels = image.kernels + size_t(y) * size_t(image.width);
  for (int x = xBegin; x < xEnd; ++x)
    visibility[x] = Blur1D(image, majorPass, x, y, kernels[x].Minor(), kernels[x].minorLength, taps);
}

ShadowFilterStats RunShadowFilter(const ShadowFilterInputs& in, const ShadowFilterParams& params,
                                  ShadowFilterOutputs& out) {
  return Run(in, params, true, out);
}

ShadowFilterStats RunShadowFilterEveryTile(const ShadowFilterInputs& in, const ShadowFilterParams& params,
                                           ShadowFilterOutputs& out) {
  return Run(in, params, false, out);
}

}  // namespace ssgi
