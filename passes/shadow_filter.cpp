// Screen-space soft-shadow filter: driver and scalar kernels (docs/pipeline.md §Shadow filter).
#include "passes/shadow_filter.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "core/check.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi {
namespace {

constexpr int kTilePixels = kShadowFilterTileSize * kShadowFilterTileSize;

bool Background(float depth) { return !(depth > 0.0f && depth < kBackgroundDepth); }

glm::vec3 ViewPosition(const ShadowFilterSetupContext& context, int x, int y, float depth) {
  return depth * glm::vec3(context.rayX[x], context.rayY[y], -1.0f);
}

// PCSS penumbra half-width in pixels (Fernando 2005, eq. 1, with the blocker distance d_b measured
// from the receiver): w = d_b * lightSize / (distance from the blocker to the light), projected with
// the receiver's pixels per metre and clamped. Non-finite products (0 * inf) mean no blur.
float PenumbraRadiusPixels(const ShadowFilterSetupContext& context, glm::vec3 position, float depth,
                           float blockerDistance) {
  const PreparedLight& light = context.light;
  float width;
  if (light.isSpot) {
    const float toLight = glm::length(light.position - position);
    width = blockerDistance * 2.0f * light.radius /
            std::max(toLight - blockerDistance, kShadowFilterMinLightToBlocker);
  } else {
    width = blockerDistance * 2.0f * light.tanAngularRadius;
  }
  const float radius = 0.5f * width * (context.pixelsPerMetreAtUnitDepth / depth);
  if (!(radius > 0.0f)) return 0.0f;
  return std::min(radius, context.maxRadius);
}

struct Kernel {
  glm::vec2 major{1.0f, 0.0f};
  float majorLength = 0.0f;
  float minorLength = 0.0f;
};

// The kernel of a pixel with penumbra half-width `radius`. SSABSS (Zheng & Saito): the screen image
// of the receiver's normal gives the minor axis, foreshortened by the TRUE |n . v| (v the unit vector
// to the camera; n.z alone is wrong away from the image centre); the major axis is perpendicular.
Kernel MakeKernel(ShadowFilter filter, glm::vec3 p, glm::vec3 n, float radius) {
  if (filter == ShadowFilter::kHard || radius < kShadowFilterMinBlurRadius) return {};
  if (filter == ShadowFilter::kSspcss) return {{1.0f, 0.0f}, radius, radius};
  const float depth = -p.z;
  // Derivative of the perspective projection (x / d, -y / d) at p along n, times d.
  const glm::vec2 projected(n.x + p.x / depth * n.z, -(n.y + p.y / depth * n.z));
  const float length = std::sqrt(glm::dot(projected, projected));
  if (length < kShadowFilterMinProjectedNormal) return {{1.0f, 0.0f}, radius, radius};
  const glm::vec2 m = projected / length;
  const float facing = std::fabs(glm::dot(n, -p)) / std::sqrt(glm::dot(p, p));
  return {{m.y, -m.x}, radius, radius * facing};
}

// What a tap reads of pixel i of the image.
struct Texel {
  glm::vec3 position;
  glm::vec3 normal;
  bool Geometry() const { return position.z < 0.0f; }
};

Texel TexelAt(const ShadowFilterTexels& texels, size_t i) {
  return {{texels.positionX[i], texels.positionY[i], texels.positionZ[i]},
          {texels.normalX[i], texels.normalY[i], texels.normalZ[i]}};
}

bool Accepts(const Texel& c, const Texel& tap) {
  return tap.Geometry() && glm::dot(tap.normal, c.normal) > kShadowFilterMinNormalDot &&
         std::fabs(glm::dot(c.normal, tap.position - c.position)) < kShadowFilterMaxPlaneDistance * -c.position.z;
}

// One 1-D pass at pixel (x, y), image index `centre`: a box of half-length `length` pixels along
// `direction`, sampled with nearest-pixel taps, bilateral, centre weight 1. taps = 0: taps at unit
// spacing, the last one weighted by the fraction of its pixel the box covers (a box filter of exact
// width, so a straight edge becomes a linear ramp of width 2 * length); taps > 0: that many equal
// taps per side at spacing length / (taps + 0.5), each standing for the same share of the box.
// Summed in a fixed order: offsets outward, negative side first. The comparisons are written so
// that NaN fails them (no blur, tap skipped) rather than reaching an integer conversion.
float Blur1D(const ShadowFilterImage& image, const float* values, int x, int y, size_t centre, glm::vec2 direction,
             float length, int taps) {
  const Texel c = TexelAt(image.texels, centre);
  if (!c.Geometry() || !(length >= kShadowFilterMinBlurRadius)) return values[centre];
  const int count = taps > 0 ? taps : int(std::ceil(length - 0.5f));
  const float spacing = taps > 0 ? length / (float(taps) + 0.5f) : 1.0f;
  float sum = values[centre], weightSum = 1.0f;
  for (int k = 1; k <= count; ++k) {
    const float t = float(k) * spacing;
    const float weight = taps > 0 ? 1.0f : std::min(1.0f, length - (t - 0.5f));
    for (const float side : {-1.0f, 1.0f}) {
      const float sx = std::floor(float(x) + 0.5f + side * t * direction.x);
      const float sy = std::floor(float(y) + 0.5f + side * t * direction.y);
      if (!(sx >= 0.0f && sy >= 0.0f && sx < float(image.width) && sy < float(image.height))) continue;
      const size_t tap = image.Index(int(sx), int(sy));
      if (!Accepts(c, TexelAt(image.texels, tap))) continue;
      sum += weight * values[tap];
      weightSum += weight;
    }
  }
  return sum / weightSum;
}

// Pixels [x0, x1) x [y0, y1) of tile `tile` (row-major tiles of kShadowFilterTileSize).
struct TileRect {
  int x0, y0, x1, y1;
};
TileRect TileBounds(int width, int height, int tilesX, size_t tile) {
  const int x0 = int(tile % size_t(tilesX)) * kShadowFilterTileSize;
  const int y0 = int(tile / size_t(tilesX)) * kShadowFilterTileSize;
  return {x0, y0, std::min(width, x0 + kShadowFilterTileSize), std::min(height, y0 + kShadowFilterTileSize)};
}

// Along a line of n tiles `stride` apart: out is 1 where a tile within `reach` of it (the line's
// own tiles only) is marked (1), from a running count of the marked tiles in that window.
void DilateLine(const char* marked, char* out, int n, size_t stride, int reach) {
  int count = 0;
  for (int i = 0; i < std::min(n, reach); ++i) count += marked[size_t(i) * stride];
  for (int i = 0; i < n; ++i) {
    if (i + reach < n) count += marked[size_t(i + reach) * stride];
    if (i - reach - 1 >= 0) count -= marked[size_t(i - reach - 1) * stride];
    out[size_t(i) * stride] = count > 0;
  }
}

// The tiles within `reach` tiles (along x and y) of a marked tile, as two 1-D passes.
std::vector<char> Dilate(const std::vector<char>& marked, int tilesX, int tilesY, int reach) {
  std::vector<char> alongX(marked.size()), out(marked.size());
  for (int ty = 0; ty < tilesY; ++ty) {
    const size_t row = size_t(ty) * size_t(tilesX);
    DilateLine(marked.data() + row, alongX.data() + row, tilesX, 1, reach);
  }
  for (int tx = 0; tx < tilesX; ++tx)
    DilateLine(alongX.data() + size_t(tx), out.data() + size_t(tx), tilesY, size_t(tilesX), reach);
  return out;
}

// The row kernels of one KernelPath, chosen once per frame.
struct RowKernels {
  decltype(&ShadowFilterPenumbraRowScalar) penumbra;
  decltype(&ShadowFilterSetupRowScalar) setup;
  decltype(&ShadowFilterMajorRowScalar) major;
  decltype(&ShadowFilterMinorRowScalar) minor;
};

RowKernels KernelsOf(KernelPath path) {
  if (path == KernelPath::kSimd)
    return {ShadowFilterPenumbraRowSimd, ShadowFilterSetupRowSimd, ShadowFilterMajorRowSimd, ShadowFilterMinorRowSimd};
  return {ShadowFilterPenumbraRowScalar, ShadowFilterSetupRowScalar, ShadowFilterMajorRowScalar,
          ShadowFilterMinorRowScalar};
}

// Which tiles the passes run on and where their set-up is stored.
struct TilePlan {
  std::vector<int32_t> tileSlots;  // per tile: its slot in the scratch, or -1 where it is not set up
  std::vector<size_t> slotTiles;   // per slot: its tile; the blurred tiles first
};

// Blur-area control (docs/design.md §5, §9). A tile is skipped, its output the hard value, when (a) no
// pixel of it has a kernel (each output uses only its own kernel in the second pass and its own tap
// in the first), or (b) every pixel within the two passes' reach (2 * maxRadius, rounded up to whole
// tiles) is shadowed or background: every accepted tap is then 0, and so is the blur. Both give the
// blur's exact bits, so skipping never changes the image. Only the tiles the taps of the blurred ones
// reach are set up.
TilePlan PlanTiles(const std::vector<ShadowFilterTileSummary>& summaries, const ShadowFilterParams& params,
                   bool skipTiles, int width, int height, ShadowFilterStats& stats) {
  const int tilesX = (width + kShadowFilterTileSize - 1) / kShadowFilterTileSize;
  const int tilesY = (height + kShadowFilterTileSize - 1) / kShadowFilterTileSize;
  const size_t tileCount = summaries.size();
  std::vector<char> hasLit(tileCount);
  for (size_t tile = 0; tile < tileCount; ++tile) hasLit[tile] = summaries[tile].litPixels > 0;
  const int twoPasses = (2 * params.maxRadiusPixels + kShadowFilterTileSize - 1) / kShadowFilterTileSize;
  const std::vector<char> litAround = Dilate(hasLit, tilesX, tilesY, twoPasses);
  std::vector<char> blurred(tileCount), setUp(tileCount);
  for (size_t tile = 0; tile < tileCount; ++tile) {
    const float maxRadius = summaries[tile].maxRadius;
    const bool hasKernel = params.filter != ShadowFilter::kHard && maxRadius >= kShadowFilterMinBlurRadius;
    blurred[tile] = !skipTiles || (hasKernel && litAround[tile]);
    if (!blurred[tile]) continue;
    ++stats.tilesBlurred;
    stats.pixels += size_t(summaries[tile].geometryPixels);
    // A tap lies within floor(length) + 1 pixels of its centre, and a kernel's lengths are at most
    // the pixel's radius (up to rounding).
    const int reach = hasKernel ? int(maxRadius) + 1 : 0;
    const TileRect r = TileBounds(width, height, tilesX, tile);
    const int tx1 = std::min(width - 1, r.x1 - 1 + reach) / kShadowFilterTileSize;
    const int ty1 = std::min(height - 1, r.y1 - 1 + reach) / kShadowFilterTileSize;
    for (int ty = std::max(0, r.y0 - reach) / kShadowFilterTileSize; ty <= ty1; ++ty)
      for (int tx = std::max(0, r.x0 - reach) / kShadowFilterTileSize; tx <= tx1; ++tx)
        setUp[size_t(ty) * size_t(tilesX) + size_t(tx)] = 1;
  }
  // The blurred tiles first: only their kernels are stored.
  TilePlan plan;
  plan.tileSlots.assign(tileCount, -1);
  for (const bool blurredFirst : {true, false})
    for (size_t tile = 0; tile < tileCount; ++tile)
      if (setUp[tile] && bool(blurred[tile]) == blurredFirst) {
        plan.tileSlots[tile] = int32_t(plan.slotTiles.size());
        plan.slotTiles.push_back(tile);
      }
  return plan;
}

// The planned tiles' slots in tile order (rows of tiles top to bottom), cut for each of the three
// tile regions into one run per thread of about equal cost. Each region runs run k on one thread,
// the same in every region and frame (ParallelForRuns): a tile's neighbours, whose scratch its
// passes read, were then mostly set up and blurred by that thread. Where the two threads sit on
// different L3 caches, running each tile wherever a thread was free made the filter about a fifth
// slower (docs/perf-log.md, "The shadow filter's tiles kept on their threads").
struct TileRuns {
  std::vector<std::vector<size_t>> setup, major, minor;
};

TileRuns MakeTileRuns(const TilePlan& plan, const std::vector<ShadowFilterTileSummary>& summaries,
                      size_t blurredSlots, size_t threads) {
  // The costs: every tile set up alike; the blur of a tile as its pixels with geometry (at least
  // one: a frame blurring every tile blurs background ones too), and the major pass's copy of an
  // unblurred tile's hard values as a tenth of a whole tile's blur; the minor pass runs on blurred
  // tiles only (cost 0: not listed). (With the blurred tiles costed alike, the 2-thread major and
  // minor runs took 15-30% longer on one thread than on the other.)
  struct Costs {
    double setup, major, minor;
  };
  const auto costs = [&](size_t tile, size_t slot) -> Costs {
    if (slot >= blurredSlots) return {1.0, 0.1 * kTilePixels, 0.0};
    const double blur = std::max(1.0, double(summaries[tile].geometryPixels));
    return {1.0, blur, blur};
  };
  Costs total{0.0, 0.0, 0.0};
  for (const size_t tile : plan.slotTiles) {
    const Costs c = costs(tile, size_t(plan.tileSlots[tile]));
    total = {total.setup + c.setup, total.major + c.major, total.minor + c.minor};
  }
  TileRuns runs{std::vector<std::vector<size_t>>(threads), std::vector<std::vector<size_t>>(threads),
                std::vector<std::vector<size_t>>(threads)};
  Costs before{0.0, 0.0, 0.0};  // of the tiles listed so far
  // Listed in the run whose share of the region's total holds the tile's middle.
  const auto list = [threads](std::vector<std::vector<size_t>>& region, double costBefore, double cost,
                              double regionCost, size_t slot) {
    if (cost == 0.0) return;
    const double middle = (costBefore + 0.5 * cost) / regionCost;
    region[std::min(threads - 1, size_t(middle * double(threads)))].push_back(slot);
  };
  for (size_t tile = 0; tile < plan.tileSlots.size(); ++tile) {
    if (plan.tileSlots[tile] < 0) continue;
    const size_t slot = size_t(plan.tileSlots[tile]);
    const Costs c = costs(tile, slot);
    list(runs.setup, before.setup, c.setup, total.setup, slot);
    list(runs.major, before.major, c.major, total.major, slot);
    list(runs.minor, before.minor, c.minor, total.minor, slot);
    before = {before.setup + c.setup, before.major + c.major, before.minor + c.minor};
  }
  // Every planned tile is set up and passed through pass 1, every blurred one through pass 2.
  const auto listed = [](const std::vector<std::vector<size_t>>& region) {
    size_t count = 0;
    for (const std::vector<size_t>& run : region) count += run.size();
    return count;
  };
  SSGI_CHECK_EQ(listed(runs.setup), plan.slotTiles.size());
  SSGI_CHECK_EQ(listed(runs.major), plan.slotTiles.size());
  SSGI_CHECK_EQ(listed(runs.minor), blurredSlots);
  return runs;
}

// The set-up of the planned tiles, stored by slot, and pass 1's output: a blurred pixel's taps stay
// near it, so this is a fraction of full-screen planes. Every element is written before it is read:
// the set-up writes each pixel of its tiles (and zeros where an edge tile leaves the image), pass 1
// each pixel of the tiles set up, and the margins before and after the arrays (ShadowFilterImage)
// are zeros.
struct Scratch {
  std::unique_ptr<float[]> storage;
  ShadowFilterTexels texels;
  ShadowFilterKernels kernels;  // of the blurred slots
  float* majorPass;
};

Scratch MakeScratch(size_t slots, size_t blurredSlots) {
  const size_t texelFloats = slots * kTilePixels, kernelFloats = blurredSlots * kTilePixels;
  const size_t margin = kShadowFilterTileSize, arrays = 8 * texelFloats + 4 * kernelFloats;
  Scratch s;
  s.storage = std::make_unique_for_overwrite<float[]>(margin + arrays + margin);
  std::fill_n(s.storage.get(), margin, 0.0f);
  std::fill_n(s.storage.get() + margin + arrays, margin, 0.0f);
  float* next = s.storage.get() + margin;
  const auto take = [&next](size_t floats) { return std::exchange(next, next + floats); };
  s.texels = {take(texelFloats), take(texelFloats), take(texelFloats), take(texelFloats),
              take(texelFloats), take(texelFloats), take(texelFloats)};
  s.kernels = {take(kernelFloats), take(kernelFloats), take(kernelFloats), take(kernelFloats)};
  s.majorPass = take(texelFloats);
  return s;
}

// Zeros for the pixels of an edge tile's slot that lie outside the image.
void ClearSlot(const Scratch& s, size_t slot, bool withKernel) {
  const ShadowFilterTexels& t = s.texels;
  for (float* a : {t.positionX, t.positionY, t.positionZ, t.normalX, t.normalY, t.normalZ, t.hard, s.majorPass})
    std::fill_n(a + slot * kTilePixels, kTilePixels, 0.0f);
  if (!withKernel) return;
  const ShadowFilterKernels& k = s.kernels;
  for (float* a : {k.majorX, k.majorY, k.majorLength, k.minorLength})
    std::fill_n(a + slot * kTilePixels, kTilePixels, 0.0f);
}

ShadowFilterStats Run(const ShadowFilterInputs& in, const ShadowFilterParams& params, bool skipTiles,
                      KernelPath path, ShadowFilterOutputs& out) {
  SSGI_CHECK(params.maxRadiusPixels >= 0);
  SSGI_CHECK(params.taps >= 0);
  SSGI_CHECK(!in.view.orthographic);
  const Stopwatch watch;
  const GBuffer& g = in.gbuffer;
  const int width = g.width(), height = g.height();
  if (out.visibility.xsize() != size_t(width) || out.visibility.ysize() != size_t(height))
    out.visibility = MakePlane<float>(size_t(width), size_t(height), 1.0f);
  const RowKernels kernels = KernelsOf(path);
  const PixelRayTables rays = MakePixelRayTables(in.view, size_t(width), size_t(height));
  const ShadowFilterSetupContext context = MakeShadowFilterSetupContext(in, params, rays);

  // Every pixel's hard value goes to the output, which is what a skipped tile keeps, and into its
  // tile's summary for the blur-area control.
  const int tilesX = (width + kShadowFilterTileSize - 1) / kShadowFilterTileSize;
  const int tilesY = (height + kShadowFilterTileSize - 1) / kShadowFilterTileSize;
  std::vector<ShadowFilterTileSummary> summaries(size_t(tilesX) * size_t(tilesY));
  ParallelFor("shadow_filter.penumbra", size_t(tilesY), [&](size_t band) {
    const int y0 = int(band) * kShadowFilterTileSize;
    for (int y = y0; y < std::min(height, y0 + kShadowFilterTileSize); ++y)
      kernels.penumbra(context, g.word[GBufferWord::kDepth].ConstRow(size_t(y)),
                       g.word[GBufferWord::kShadowTerm].ConstRow(size_t(y)), 0, y, width,
                       out.visibility.MutableRow(size_t(y)), summaries.data() + band * size_t(tilesX));
  });
  ShadowFilterStats stats;
  stats.tiles = summaries.size();
  const TilePlan plan = PlanTiles(summaries, params, skipTiles, width, height, stats);
  const size_t blurredSlots = stats.tilesBlurred;
  const Scratch scratch = MakeScratch(plan.slotTiles.size(), blurredSlots);
  const ShadowFilterImage image{scratch.texels, scratch.kernels, plan.tileSlots.data(), width, height, tilesX};

  const TileRuns runs = MakeTileRuns(plan, summaries, blurredSlots, ParallelThreads());
  ParallelForRuns("shadow_filter.setup", runs.setup, [&](size_t slot) {
    const TileRect r = TileBounds(width, height, tilesX, plan.slotTiles[slot]);
    const bool withKernel = slot < blurredSlots;
    if (r.x1 - r.x0 < kShadowFilterTileSize || r.y1 - r.y0 < kShadowFilterTileSize)
      ClearSlot(scratch, slot, withKernel);
    for (int y = r.y0; y < r.y1; ++y) {
      const size_t i = image.Index(r.x0, y);
      const ShadowFilterKernels rowKernels = scratch.kernels + i;
      kernels.setup(context, g.word[GBufferWord::kNormalRoughness].ConstRow(size_t(y)) + r.x0,
                    g.word[GBufferWord::kDepth].ConstRow(size_t(y)) + r.x0,
                    g.word[GBufferWord::kShadowTerm].ConstRow(size_t(y)) + r.x0, r.x0, y, r.x1 - r.x0,
                    scratch.texels + i, withKernel ? &rowKernels : nullptr);
    }
  });
  // Pass 1 along each pixel's major axis; the tiles around the blurred ones keep their hard values,
  // which is what the blur would give there.
  ParallelForRuns("shadow_filter.major", runs.major, [&](size_t slot) {
    if (slot >= blurredSlots) {
      std::copy_n(scratch.texels.hard + slot * kTilePixels, kTilePixels, scratch.majorPass + slot * kTilePixels);
      return;
    }
    const TileRect r = TileBounds(width, height, tilesX, plan.slotTiles[slot]);
    for (int y = r.y0; y < r.y1; ++y)
      kernels.major(image, scratch.texels.hard, params.taps, y, r.x0, r.x1, scratch.majorPass + image.Index(r.x0, y));
  });
  // Pass 2 along the minor axis of the output pixel.
  ParallelForRuns("shadow_filter.minor", runs.minor, [&](size_t slot) {
    const TileRect r = TileBounds(width, height, tilesX, plan.slotTiles[slot]);
    for (int y = r.y0; y < r.y1; ++y)
      kernels.minor(image, scratch.majorPass, params.taps, y, r.x0, r.x1,
                    out.visibility.MutableRow(size_t(y)) + r.x0);
  });
  stats.ms = watch.Milliseconds();
  return stats;
}

}  // namespace

ShadowFilterSetupContext MakeShadowFilterSetupContext(const ShadowFilterInputs& in, const ShadowFilterParams& params,
                                                      const PixelRayTables& rays) {
  return {in.light,
          rays.x.data(),
          rays.y.data(),
          in.gbuffer.normalEncoding,
          params.filter,
          float(params.maxRadiusPixels),
          float(in.gbuffer.height()) / (2.0f * in.view.halfY)};
}

void ShadowFilterPenumbraRowScalar(const ShadowFilterSetupContext& context, const uint32_t* word2,
                                   const uint32_t* word3, int x, int y, int count, float* hard,
                                   ShadowFilterTileSummary* tiles) {
  for (int i = 0; i < count; ++i) {
    const float depth = UnpackDepth(word2[i]);
    if (Background(depth)) {
      hard[i] = 1.0f;
      continue;
    }
    hard[i] = UnpackHardShadow(word3[i]) ? 0.0f : 1.0f;
    const float radius =
        PenumbraRadiusPixels(context, ViewPosition(context, x + i, y, depth), depth, UnpackBlockerDistance(word3[i]));
    ShadowFilterTileSummary& tile = tiles[(x + i) / kShadowFilterTileSize];
    tile.maxRadius = std::max(tile.maxRadius, radius);
    ++tile.geometryPixels;
    tile.litPixels += hard[i] != 0.0f;
  }
}

void ShadowFilterSetupRowScalar(const ShadowFilterSetupContext& context, const uint32_t* word1, const uint32_t* word2,
                                const uint32_t* word3, int x, int y, int count, const ShadowFilterTexels& texels,
                                const ShadowFilterKernels* kernels) {
  for (int i = 0; i < count; ++i) {
    const float depth = UnpackDepth(word2[i]);
    glm::vec3 position(0.0f), normal(0.0f);
    Kernel kernel;
    float hard = 1.0f;
    if (!Background(depth)) {
      position = ViewPosition(context, x + i, y, depth);
      normal = UnpackNormal(word1[i], context.normalEncoding);
      hard = UnpackHardShadow(word3[i]) ? 0.0f : 1.0f;
      if (kernels) {
        const float radius = PenumbraRadiusPixels(context, position, depth, UnpackBlockerDistance(word3[i]));
        kernel = MakeKernel(context.filter, position, normal, radius);
      }
    }
    texels.positionX[i] = position.x;
    texels.positionY[i] = position.y;
    texels.positionZ[i] = position.z;
    texels.normalX[i] = normal.x;
    texels.normalY[i] = normal.y;
    texels.normalZ[i] = normal.z;
    texels.hard[i] = hard;
    if (kernels) {
      kernels->majorX[i] = kernel.major.x;
      kernels->majorY[i] = kernel.major.y;
      kernels->majorLength[i] = kernel.majorLength;
      kernels->minorLength[i] = kernel.minorLength;
    }
  }
}

void ShadowFilterMajorRowScalar(const ShadowFilterImage& image, const float* values, int taps, int y, int xBegin,
                                int xEnd, float* out) {
  const ShadowFilterKernels& k = image.kernels;
  for (int x = xBegin; x < xEnd; ++x) {
    const size_t i = image.Index(x, y);
    out[x - xBegin] = Blur1D(image, values, x, y, i, {k.majorX[i], k.majorY[i]}, k.majorLength[i], taps);
  }
}

void ShadowFilterMinorRowScalar(const ShadowFilterImage& image, const float* values, int taps, int y, int xBegin,
                                int xEnd, float* out) {
  const ShadowFilterKernels& k = image.kernels;
  for (int x = xBegin; x < xEnd; ++x) {
    const size_t i = image.Index(x, y);
    out[x - xBegin] = Blur1D(image, values, x, y, i, {-k.majorY[i], k.majorX[i]}, k.minorLength[i], taps);
  }
}

ShadowFilterStats RunShadowFilter(const ShadowFilterInputs& in, const ShadowFilterParams& params,
                                  ShadowFilterOutputs& out, KernelPath kernels) {
  return Run(in, params, true, kernels, out);
}

ShadowFilterStats RunShadowFilterEveryTile(const ShadowFilterInputs& in, const ShadowFilterParams& params,
                                           ShadowFilterOutputs& out, KernelPath kernels) {
  return Run(in, params, false, kernels, out);
}

}  // namespace ssgi
