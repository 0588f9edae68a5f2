// The G-buffer's edge coverage (passes/gbuffer.h, docs/pipeline.md §Edge coverage): the rasterizer's
// triangle per pixel, with the triangle's own screen-space edges, gives the share of each pixel on
// either side of a geometric edge.
#include <algorithm>
#include <array>
#include <cmath>
#include <glm/glm.hpp>
#include <utility>
#include <vector>

#include "core/check.h"
#include "passes/gbuffer.h"

namespace ssgi {
namespace {

// The weights one pair of neighbouring pixels gives each other: `towardB` is the share of pixel a
// covered by b's surface, `towardA` that of b covered by a's.
struct PairWeights {
  double towardB = 0.0, towardA = 0.0;
};

// The screen-space edges of the scene's triangles seen from `view`.
class EdgeProjection {
 public:
  EdgeProjection(const Scene& scene, const ViewProjection& view)
      : scene_(scene), viewProjection_(view.viewProjection), width_(view.width), height_(view.height) {}

  // Pixels a = (ax, ay) and b (its right neighbour when alongX, else the one below) across a
  // geometric edge: the edge of the nearer pixel's triangle that the segment between the two
  // centres leaves it through, if its line runs along the pair's minor axis.
  PairWeights Pair(uint32_t triangleA, uint32_t triangleB, float depthA, float depthB, int ax, int ay,
                   bool alongX) const {
    const int bx = ax + (alongX ? 1 : 0), by = ay + (alongX ? 0 : 1);
    // The nearer surface; the background is never nearer, and a tie takes a.
    const bool aFront = triangleB == kNoTriangle || (triangleA != kNoTriangle && depthA <= depthB);
    const uint32_t front = aFront ? triangleA : triangleB;
    const glm::dvec3 centreA(ax + 0.5, ay + 0.5, 1.0), centreB(bx + 0.5, by + 0.5, 1.0);
    const glm::dvec3& frontCentre = aFront ? centreA : centreB;
    const glm::dvec3& backCentre = aFront ? centreB : centreA;
    const Lines& lines = LinesOf(front);
    glm::dvec3 line{0.0};
    double lineFront = 0.0, lineBack = 0.0, exit = 2.0;
    for (int i = 0; i < 3; ++i) {
      // The edge's line a x + b y + c = 0, oriented positive on the front centre's side: that
      // centre is inside the triangle, the rasterizer found it there.
      glm::dvec3 edge = lines.edge[i];
      double eFront = glm::dot(edge, frontCentre), eBack = glm::dot(edge, backCentre);
      if (eFront < 0.0) {
        edge = -edge;
        eFront = -eFront;
        eBack = -eBack;
      }
      if (!(eBack < 0.0)) continue;  // both centres on its inner side: not between them
      // Where the segment from the front centre crosses it, as a share of the segment: the first
      // crossing is where it leaves the triangle.
      const double t = eFront / (eFront - eBack);
      if (t < exit) {
        exit = t;
        line = edge;
        lineFront = eFront;
        lineBack = eBack;
      }
    }
    const double length = std::sqrt(line.x * line.x + line.y * line.y);
    // No edge between the centres (a clipped or cut-out boundary) or not along this pair's axis.
    if (exit > 1.0 || !(length > 0.0) || !std::isfinite(length)) return {};
    const double nx = line.x / length, ny = line.y / length;
    if (alongX ? std::abs(nx) < std::abs(ny) : std::abs(ny) <= std::abs(nx)) return {};
    const double frontOutside = 1.0 - BoxCoverage(lineFront / length, nx, ny);
    const double backInside = BoxCoverage(lineBack / length, nx, ny);
    return aFront ? PairWeights{frontOutside, backInside} : PairWeights{backInside, frontOutside};
  }

 private:
  // A triangle's three edge lines, L_i = h_i x h_(i+1), kept for the pairs along the same edge: a
  // small cache indexed by the triangle's low bits (the lines do not depend on which pair asks).
  struct Lines {
    uint32_t triangle = kNoTriangle;
    glm::dvec3 edge[3];
  };
  const Lines& LinesOf(uint32_t triangle) const {
    Lines& lines = cache_[triangle % kCacheSize];
    if (lines.triangle == triangle) return lines;
    const uint32_t* index = &scene_.mesh.indices[3 * size_t(triangle)];
    glm::dvec3 vertex[3];
    for (int i = 0; i < 3; ++i) vertex[i] = HomogeneousPixel(scene_.mesh.positions[index[i]]);
    for (int i = 0; i < 3; ++i) lines.edge[i] = glm::cross(vertex[i], vertex[(i + 1) % 3]);
    lines.triangle = triangle;
    return lines;
  }
  static constexpr size_t kCacheSize = 256;

  // A vertex in homogeneous pixel coordinates (x w, y w, w), pixel centres at +0.5: the
  // rasterizer's screen mapping before its division by w.
  glm::dvec3 HomogeneousPixel(const glm::vec3& world) const {
    const glm::dvec4 clip = viewProjection_ * glm::dvec4(glm::dvec3(world), 1.0);
    return {(0.5 * clip.x + 0.5 * clip.w) * double(width_), (0.5 * clip.w - 0.5 * clip.y) * double(height_), clip.w};
  }

  const Scene& scene_;
  mutable std::array<Lines, kCacheSize> cache_;
  glm::dmat4 viewProjection_;
  int width_, height_;
};

// Calls f(x) for each x < count where a[x] != b[x], testing blocks of 16 at once first.
template <class F>
void ForEachDifference(const uint32_t* a, const uint32_t* b, size_t count, const F& f) {
  constexpr size_t kBlock = 16;
  for (size_t x0 = 0; x0 < count; x0 += kBlock) {
    const size_t end = std::min(count, x0 + kBlock);
    uint32_t differ = 0;
    for (size_t x = x0; x < end; ++x) differ |= a[x] ^ b[x];
    if (differ == 0) continue;
    for (size_t x = x0; x < end; ++x)
      if (a[x] != b[x]) f(x);
  }
}

// A weight as the word's byte: 1/256 units, rounded, at most 255.
uint32_t WeightCode(double w) { return uint32_t(std::min(255.0, std::floor(w * 256.0 + 0.5))); }

}  // namespace

bool GeometricEdge(uint32_t triangleA, uint32_t triangleB, float depthA, float depthB, const uint32_t* materials) {
  if (triangleA == triangleB) return false;
  if (triangleA == kNoTriangle || triangleB == kNoTriangle) return true;
  if (materials[triangleA] != materials[triangleB]) return true;
  const float nearer = std::min(depthA, depthB), farther = std::max(depthA, depthB);
  return farther > nearer * (1.0f + kEdgeDepthJump);
}

double BoxCoverage(double distance, double nx, double ny) {
  // The square's width across the line's normal, integrated from the centre: its projection on
  // the normal is a trapezoid of half widths h1 (flat top) and h2 (feet).
  const double a = std::max(std::abs(nx), std::abs(ny)), b = std::min(std::abs(nx), std::abs(ny));
  const double h1 = 0.5 * (a - b), h2 = 0.5 * (a + b);
  const double t = std::abs(distance);
  double half;
  if (t >= h2) {
    half = 0.5;
  } else if (t <= h1) {
    half = t / a;
  } else {
    const double foot = h2 - t;
    half = h1 / a + (b * b - foot * foot) / (2.0 * a * b);
  }
  return distance >= 0.0 ? 0.5 + half : 0.5 - half;
}

size_t EdgeCoverageRows(const Scene& scene, const ViewProjection& view, const VisibilityBuffer& visibility, size_t y0,
                        size_t y1, Plane<uint32_t>& coverage) {
  const size_t width = size_t(view.width), height = size_t(view.height);
  const uint32_t* materials = scene.mesh.materials.data();
  const EdgeProjection projection(scene, view);
  // The view depths word 2 holds, from the keys the raster wrote beside the triangles: a row's at
  // once (a loop the compiler vectorises) rather than a division per pixel of each pair.
  const auto depthsOf = [&](size_t y, std::vector<float>& depths) {
    const float* keys = visibility.depthKey.ConstRow(y);
    for (size_t x = 0; x < width; ++x) depths[x] = view.DepthFromKey(keys[x]);
  };
  std::vector<float> depthAbove(width), depthHere(width), depthBelow(width);
  // The pair of (x, y) with its right (alongX) or lower neighbour, `depthA` the depths of row y and
  // `depthB` those of the neighbour's row; most pairs share a triangle.
  const auto pair = [&](size_t x, size_t y, bool alongX, const std::vector<float>& depthA,
                        const std::vector<float>& depthB) -> PairWeights {
    const size_t bx = x + (alongX ? 1 : 0), by = y + (alongX ? 0 : 1);
    const uint32_t ta = visibility.triangle.ConstRow(y)[x], tb = visibility.triangle.ConstRow(by)[bx];
    if (ta == tb) return {};
    const float da = depthA[x], db = depthB[bx];
    if (!GeometricEdge(ta, tb, da, db, materials)) return {};
    return projection.Pair(ta, tb, da, db, int(x), int(y), alongX);
  };
  // Per row: the zero words, then the pixels whose triangle differs from a neighbour's, gathered.
  std::vector<std::array<double, 4>> weights(width, {0.0, 0.0, 0.0, 0.0});  // left, right, up, down
  std::vector<uint8_t> touched(width, 0);
  std::vector<size_t> pixels;
  std::vector<std::pair<size_t, double>> fromAbove;  // the next row's weights toward this row
  size_t edgePixels = 0;
  if (y0 > 0 && y0 < y1) depthsOf(y0 - 1, depthAbove);
  if (y0 < y1) depthsOf(y0, depthHere);
  for (size_t y = y0; y < y1; ++y) {
    if (y + 1 < height) depthsOf(y + 1, depthBelow);
    const uint32_t* row = visibility.triangle.ConstRow(y);
    uint32_t* out = coverage.MutableRow(y);
    std::fill_n(out, width, 0u);
    pixels.clear();
    const auto add = [&](size_t x, int k, double w) {
      if (w == 0.0) return;
      if (!touched[x]) pixels.push_back(x);
      touched[x] = 1;
      weights[x][size_t(k)] = w;
    };
    // Blocks of pixels whose triangles all equal their neighbours' are skipped whole.
    ForEachDifference(row, row + 1, width - 1, [&](size_t x) {
      const PairWeights w = pair(x, y, true, depthHere, depthHere);
      add(x, 1, w.towardB);
      add(x + 1, 0, w.towardA);
    });
    // The pairs with the row above: the band's first row computes them, later rows take them from
    // the row above's pairs with the row below.
    if (y == y0 && y > 0)
      ForEachDifference(row, visibility.triangle.ConstRow(y - 1), width,
                        [&](size_t x) { add(x, 2, pair(x, y - 1, false, depthAbove, depthHere).towardA); });
    for (const auto& [x, w] : fromAbove) add(x, 2, w);
    fromAbove.clear();
    if (y + 1 < height)
      ForEachDifference(row, visibility.triangle.ConstRow(y + 1), width, [&](size_t x) {
        const PairWeights w = pair(x, y, false, depthHere, depthBelow);
        add(x, 3, w.towardB);
        if (w.towardA != 0.0) fromAbove.emplace_back(x, w.towardA);
      });
    for (size_t x : pixels) {
      uint32_t code[4], sum = 0;
      for (size_t k = 0; k < 4; ++k) sum += code[k] = WeightCode(weights[x][k]);
      // Overlapping shares (a corner, a feature thinner than the pixel) scaled to the whole pixel.
      if (sum > 256)
        for (uint32_t& c : code) c = c * 256 / sum;
      out[x] = EdgeCoverageWord(code[0], code[1], code[2], code[3]);
      edgePixels += out[x] != 0;
      weights[x] = {0.0, 0.0, 0.0, 0.0};
      touched[x] = 0;
    }
    std::swap(depthHere, depthBelow);
  }
  return edgePixels;
}

}  // namespace ssgi
