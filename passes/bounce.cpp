// Diffuse bounce and ambient occlusion: the driver and the scalar row kernels, the readable
// definition (docs/pipeline.md §Diffuse bounce and ambient occlusion (visibility bitmask)).
#include "passes/bounce.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <vector>

#include "core/check.h"
#include "core/color.h"
#include "core/fast_math.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi {
namespace {

constexpr float kHalfPi = 1.57079633f;  // the float nearest pi / 2

bool HasGeometry(float depth) { return depth >= kBounceMinDepth && depth <= kBounceMaxDepth; }

// The view-space ray (z = -1) through full-resolution image position (x + 0.5, y + 0.5): the centre
// of pixel (x, y) for whole x, y.
glm::vec3 Ray(const BounceSetup& setup, float x, float y) {
  return {(x + 0.5f) * setup.rayScaleX + setup.rayOffsetX, (y + 0.5f) * setup.rayScaleY + setup.rayOffsetY, -1.0f};
}

// The view-space point at depth d on the centre ray of full-resolution pixel (X, Y).
glm::vec3 ViewPosition(const BounceSetup& setup, int x, int y, float d) { return d * Ray(setup, float(x), float(y)); }

float Dot(const glm::vec3& a, const glm::vec3& b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }

// The direction of a normal code without its length (kBounceOct24Scale).
glm::vec3 RawNormal(uint32_t code, NormalEncoding encoding) {
  if (encoding == NormalEncoding::kXyz8) {
    return {float(code & 0xFFu) * kBounceXyz8Scale - 1.0f, float((code >> 8) & 0xFFu) * kBounceXyz8Scale - 1.0f,
            float((code >> 16) & 0xFFu) * kBounceXyz8Scale - 1.0f};
  }
  float x = float(code & 0xFFFu) * kBounceOct24Scale - 1.0f;
  float y = float((code >> 12) & 0xFFFu) * kBounceOct24Scale - 1.0f;
  const float z = (1.0f - std::fabs(x)) - std::fabs(y);
  const float fold = std::max(-z, 0.0f);
  x = x >= 0.0f ? x - fold : x + fold;
  y = y >= 0.0f ? y - fold : y + fold;
  return {x, y, z};
}

// The sectors [start, end) of a 32-bit mask: Below(k) has bits 0 .. k - 1 set, for k in [0, 32].
uint32_t Below(int k) { return k >= 32 ? 0xFFFFFFFFu : (uint32_t(1) << k) - 1u; }

// One slice of one pixel: its frame and the cosine-weighted sector map (docs/pipeline.md).
struct Slice {
  glm::vec3 o;    // unit direction in the slice plane perpendicular to v, toward the + side
  float halfCos;  // cos(gamma) / 2, gamma the projected normal's angle from v toward o
  float halfSin;  // sin(gamma) / 2
  float cosGamma, sinGamma;
  float q0;      // Q at the hemisphere's start, gamma - pi / 2
  float invI;    // 1 / (cos gamma + gamma sin gamma), the slice's cosine-weighted measure
  float weight;  // |n projected| (cos gamma + gamma sin gamma); 0: the slice is skipped
};

Slice MakeSlice(const glm::vec3& v, const glm::vec3& n, float cx, float cy) {
  Slice s;
  // The screen direction (cx, cy) (y down) is the view-space direction (cx, -cy, 0).
  const float dv = cx * v.x - cy * v.y;
  const glm::vec3 along{cx - dv * v.x, -cy - dv * v.y, -(dv * v.z)};
  const float invAlong = 1.0f / std::sqrt(Dot(along, along));
  s.o = {along.x * invAlong, along.y * invAlong, along.z * invAlong};
  const float no = Dot(n, s.o), nv = Dot(n, v);
  const float projected = std::sqrt(no * no + nv * nv);
  // A normal facing away from the camera within the slice is taken at the slice's edge (gamma =
  // +-pi/2, as XeGTAO clamps it): the hemisphere is then one side of the view direction.
  const bool facing = nv > 0.0f && projected > 0.0f;
  s.cosGamma = facing ? nv / projected : 0.0f;
  s.sinGamma = facing ? no / projected : (no < 0.0f ? -1.0f : 1.0f);
  const float absGamma = AcosPoly(s.cosGamma);
  const float gamma = s.sinGamma < 0.0f ? -absGamma : absGamma;
  s.halfCos = 0.5f * s.cosGamma;
  s.halfSin = 0.5f * s.sinGamma;
  const float measure = s.cosGamma + gamma * s.sinGamma;
  s.invI = 1.0f / measure;
  s.q0 = (s.cosGamma + (gamma - kHalfPi) * s.sinGamma) * -0.5f;
  s.weight = projected > 0.0f ? projected * measure : 0.0f;
  return s;
}

// Where the direction (x, y) of the slice plane (x along o, y along v; r2 = x^2 + y^2 > 0) on side
// `positive` falls in the slice's cosine-weighted measure, from 0 at the hemisphere's start (gamma
// - pi/2) to 1 at its end (gamma + pi/2): u = (Q(theta) - Q0) / I with Q(theta) the integral of
// cos(t - gamma) |sin t| from 0 to theta (docs/pipeline.md gives the derivation). Directions below
// the tangent plane go to the end of their side.
float SectorPosition(const Slice& s, float x, float y, bool positive) {
  const float length = std::sqrt(x * x + y * y);
  const float inv = 1.0f / length;
  const float c = std::clamp(y * inv, -1.0f, 1.0f);
  const float a = std::fabs(x) * inv;
  const float theta = AcosPoly(c);
  const float sideCos = s.halfCos * (a * a);
  const float q = (positive ? sideCos : -sideCos) + s.halfSin * (theta - c * a);
  const float sideSin = positive ? a : -a;
  if (c * s.cosGamma + sideSin * s.sinGamma < 0.0f) return positive ? 1.0f : 0.0f;
  return std::clamp((q - s.q0) * s.invI, 0.0f, 1.0f);
}

// The mask of the sectors whose centres lie in [lo, hi] of the measure (sector k's centre is
// (k + 0.5) / sectors).
uint32_t SectorMask(float lo, float hi, int sectors) {
  const float n = float(sectors);
  const int start = int(lo * n + 0.5f);
  const int end = int(hi * n + 0.5f);
  return Below(end) & ~Below(start);
}

struct Pixel {
  float visibility = 1.0f;
  glm::vec3 bounce{0.0f};
};

// The march of half-resolution pixel (i, j).
Pixel MarchPixel(const BounceSetup& setup, const BounceHalfView& half, int i, int j, uint64_t& taps) {
  Pixel out;
  const size_t centre = size_t(j) * half.stride + size_t(i);
  const float d = half.depth[centre];
  if (!HasGeometry(d)) return out;
  const glm::vec3 n{half.normal[0][centre], half.normal[1][centre], half.normal[2][centre]};
  const glm::vec3 p = ViewPosition(setup, 2 * i, 2 * j, d);
  const float invLength = 1.0f / std::sqrt(Dot(p, p));
  const glm::vec3 v{-(p.x * invLength), -(p.y * invLength), -(p.z * invLength)};
  const float radius = std::min(setup.radiusPixelsAtUnitDepth / d, setup.maxRadiusPixels) * 0.5f;
  const int rotation = BounceRotationPhase(i, j);
  const int jitter = BounceJitterPhase(rotation);
  const float sectors = float(setup.sectors);

  float weightSum = 0.0f, visibilitySum = 0.0f;
  glm::vec3 bounceSum{0.0f};
  for (int k = 0; k < setup.slices; ++k) {
    const float cx = setup.directionX[16 * k + rotation];
    const float cy = setup.directionY[16 * k + rotation];
    const Slice slice = MakeSlice(v, n, cx, cy);
    if (!(slice.weight > 0.0f)) continue;
    uint32_t occluded = 0;
    glm::vec3 sliceBounce{0.0f};
    for (int step = 0; step < setup.steps; ++step) {
      const float distance = kBounceMinTapDistance + setup.stepSpread[16 * step + jitter] * radius;
      const float offsetX = distance * cx, offsetY = distance * cy;
      for (const bool positive : {true, false}) {
        // The sample lies on the slice's screen line; the pixel read is the nearest one.
        const float lineX = float(i) + (positive ? offsetX : -offsetX);
        const float lineY = float(j) + (positive ? offsetY : -offsetY);
        const float tx = float(i) + std::floor((positive ? offsetX : -offsetX) + 0.5f);
        const float ty = float(j) + std::floor((positive ? offsetY : -offsetY) + 0.5f);
        if (!(tx >= 0.0f && tx < float(setup.halfWidth) && ty >= 0.0f && ty < float(setup.halfHeight))) continue;
        ++taps;
        const size_t tap = size_t(ty) * half.stride + size_t(tx);
        const float tapDepth = half.depth[tap];
        if (!HasGeometry(tapDepth)) continue;
        // A sample within kBounceMinRise of the pixel's tangent plane (or below it) covers no sector:
        // the pixel's own surface, and what barely rises from it.
        const glm::vec3 pixelRay = Ray(setup, 2.0f * tx, 2.0f * ty);
        const glm::vec3 own = tapDepth * pixelRay - p;
        const float rise = Dot(n, own);
        if (!(rise > 0.0f) || (rise * rise) * kBounceMinRiseInverseSquare <= Dot(own, own)) continue;
        // The point where the line's ray meets the pixel's tangent plane, so that the sample lies in
        // the slice: a pixel up to half a pixel off the line is off the slice's plane, which on a
        // surface seen at a grazing angle puts it far above or below the slice's view of that
        // surface. Where the plane is too oblique to the rays (the depth ratio outside [1/2, 2]), the
        // pixel's own point.
        const glm::vec3 tapNormal = RawNormal(half.normalCode[tap], setup.encoding);
        const glm::vec3 lineRay = Ray(setup, 2.0f * lineX, 2.0f * lineY);
        const float ratio = Dot(tapNormal, pixelRay) / Dot(tapNormal, lineRay);
        const bool onPlane = ratio >= 0.5f && ratio <= 2.0f;
        const glm::vec3 point = onPlane ? (tapDepth * ratio) * lineRay : tapDepth * pixelRay;
        const glm::vec3 delta = point - p;
        const float x = Dot(delta, slice.o), y = Dot(delta, v);
        if (x == 0.0f && y == 0.0f) continue;
        const float front = SectorPosition(slice, x, y, positive);
        const float back = SectorPosition(slice, x, y - setup.thickness, positive);
        const uint32_t mask = SectorMask(std::min(front, back), std::max(front, back), setup.sectors);
        const uint32_t fresh = mask & ~occluded;
        occluded |= mask;
        if (fresh == 0) continue;
        // Only a surface that faces the pixel sends it light; its back shows the lit image's front.
        if (!(Dot(tapNormal, delta) < 0.0f)) continue;
        const float count = float(std::popcount(fresh));
        sliceBounce += glm::vec3(count * half.lit[0][tap], count * half.lit[1][tap], count * half.lit[2][tap]);
      }
    }
    weightSum += slice.weight;
    visibilitySum += slice.weight * (1.0f - float(std::popcount(occluded)) / sectors);
    bounceSum += slice.weight * sliceBounce;
  }
  if (!(weightSum > 0.0f)) return out;
  out.visibility = visibilitySum / weightSum;
  const float norm = weightSum * sectors;
  out.bounce = {bounceSum.x / norm, bounceSum.y / norm, bounceSum.z / norm};
  return out;
}

// The filter's and the upsample's weight of a neighbour at view position c with unit normal m, for
// a pixel at p with unit normal n: linear in the neighbour's distance from the pixel's tangent plane
// (0 at invTolerance's reciprocal), times max(n.m, 0)^8.
float MatchWeight(const glm::vec3& p, const glm::vec3& n, float invTolerance, const glm::vec3& c, const glm::vec3& m) {
  const float plane = std::max(0.0f, 1.0f - std::fabs(Dot(n, c - p)) * invTolerance);
  const float facing = std::max(0.0f, Dot(n, m));
  const float f2 = facing * facing, f4 = f2 * f2;
  return plane * (f4 * f4);
}

}  // namespace

BounceSetup MakeBounceSetup(const ViewProjection& view, const BounceParams& params, NormalEncoding encoding) {
  SSGI_CHECK(!view.orthographic);
  SSGI_CHECK(params.slices >= 1 && params.slices <= kBounceMaxSlices);
  SSGI_CHECK(params.steps >= 1 && params.steps <= kBounceMaxSteps);
  SSGI_CHECK(params.sectors >= 1 && params.sectors <= kBounceMaxSectors);
  SSGI_CHECK(params.radius >= 0.0f && std::isfinite(params.radius));
  SSGI_CHECK(params.maxRadiusPixels >= 0.0f && std::isfinite(params.maxRadiusPixels));
  SSGI_CHECK(params.thickness >= 0.0f && std::isfinite(params.thickness));
  SSGI_CHECK(params.depthTolerance > 0.0f && std::isfinite(params.depthTolerance));
  BounceSetup setup;
  setup.width = view.width;
  setup.height = view.height;
  setup.halfWidth = (view.width + 1) / 2;
  setup.halfHeight = (view.height + 1) / 2;
  setup.rayScaleX = (2.0f * view.halfX) / float(view.width);
  setup.rayOffsetX = -view.halfX;
  setup.rayScaleY = -((2.0f * view.halfY) / float(view.height));
  setup.rayOffsetY = view.halfY;
  setup.radiusPixelsAtUnitDepth = params.radius * (float(view.height) / (2.0f * view.halfY));
  setup.maxRadiusPixels = params.maxRadiusPixels;
  setup.thickness = params.thickness;
  setup.slices = params.slices;
  setup.steps = params.steps;
  setup.sectors = params.sectors;
  setup.depthTolerance = params.depthTolerance;
  setup.encoding = encoding;
  // Per-frame set-up, so libm: the angle in double, rounded once (a port uploads the table).
  for (int k = 0; k < params.slices; ++k) {
    for (int r = 0; r < 16; ++r) {
      const double angle = 3.14159265358979323846 * (double(k) + (double(r) + 0.5) / 16.0) / double(params.slices);
      setup.directionX[16 * k + r] = float(std::cos(angle));
      setup.directionY[16 * k + r] = float(std::sin(angle));
    }
  }
  for (int step = 0; step < params.steps; ++step) {
    for (int q = 0; q < 16; ++q) {
      const float rank = (float(step) + (float(q) + 0.5f) / 16.0f) / float(params.steps);
      setup.stepSpread[16 * step + q] = rank * rank;
    }
  }
  return setup;
}

void BouncePrepareRowScalar(const BounceSetup& setup, const uint32_t* word1Row, const uint32_t* word2Row,
                            const float* const litRow[3], float* depth, float* const normal[3], uint32_t* normalCode,
                            float* const lit[3]) {
  for (int i = 0; i < setup.halfWidth; ++i) {
    const size_t x = 2 * size_t(i);
    const float d = UnpackDepth(word2Row[x]);
    const bool geometry = HasGeometry(d);
    depth[i] = geometry ? d : kBackgroundDepth;
    const glm::vec3 n = geometry ? UnpackNormal(word1Row[x], setup.encoding) : glm::vec3(0.0f);
    normalCode[i] = geometry ? word1Row[x] & 0xFFFFFFu : 0u;
    for (int c = 0; c < 3; ++c) {
      normal[c][i] = n[c];
      lit[c][i] = SanitizeRadiance(litRow[c][x]);
    }
  }
}

uint64_t BounceMarchRowScalar(const BounceSetup& setup, const BounceHalfView& half, int j, float* visibility,
                              float* const bounce[3]) {
  uint64_t taps = 0;
  for (int i = 0; i < setup.halfWidth; ++i) {
    const Pixel pixel = MarchPixel(setup, half, i, j, taps);
    visibility[i] = pixel.visibility;
    for (int c = 0; c < 3; ++c) bounce[c][i] = pixel.bounce[c];
  }
  return taps;
}

void BounceFilterRowScalar(const BounceSetup& setup, const BounceHalfView& half, int j, bool vertical,
                           const float* sourceVisibility, const float* const sourceBounce[3], float* visibility,
                           float* const bounce[3]) {
  for (int i = 0; i < setup.halfWidth; ++i) {
    const size_t centre = size_t(j) * half.stride + size_t(i);
    const float d = half.depth[centre];
    Pixel out;
    if (HasGeometry(d)) {
      const glm::vec3 p = ViewPosition(setup, 2 * i, 2 * j, d);
      const glm::vec3 n{half.normal[0][centre], half.normal[1][centre], half.normal[2][centre]};
      const float invTolerance = 1.0f / (setup.depthTolerance * d);
      float weightSum = 0.0f, visibilitySum = 0.0f;
      glm::vec3 bounceSum{0.0f};
      for (int t = -kBounceFilterRadius; t <= kBounceFilterRadius; ++t) {
        const int ii = vertical ? i : i + t, jj = vertical ? j + t : j;
        float weight = 0.0f, v = 0.0f;
        glm::vec3 b{0.0f};
        if (ii >= 0 && ii < setup.halfWidth && jj >= 0 && jj < setup.halfHeight) {
          const size_t at = size_t(jj) * half.stride + size_t(ii);
          const float neighbourDepth = half.depth[at];
          if (HasGeometry(neighbourDepth)) {
            const glm::vec3 c = ViewPosition(setup, 2 * ii, 2 * jj, neighbourDepth);
            const glm::vec3 m{half.normal[0][at], half.normal[1][at], half.normal[2][at]};
            weight = kBounceFilterSpatial[t + kBounceFilterRadius] * MatchWeight(p, n, invTolerance, c, m);
            v = sourceVisibility[at];
            b = {sourceBounce[0][at], sourceBounce[1][at], sourceBounce[2][at]};
          }
        }
        weightSum += weight;
        visibilitySum += weight * v;
        bounceSum += weight * b;
      }
      out.visibility = visibilitySum / weightSum;
      out.bounce = {bounceSum.x / weightSum, bounceSum.y / weightSum, bounceSum.z / weightSum};
    }
    visibility[i] = out.visibility;
    for (int c = 0; c < 3; ++c) bounce[c][i] = out.bounce[c];
  }
}

void BounceUpsampleRowScalar(const BounceSetup& setup, const BounceHalfView& half, int y, const uint32_t* word1Row,
                             const uint32_t* word2Row, float* visibility, float* const bounce[3]) {
  const int j0 = y >> 1, j1 = std::min(j0 + (y & 1), setup.halfHeight - 1);
  const float by0 = (y & 1) ? 0.5f : 1.0f, by1 = 1.0f - by0;
  for (int x = 0; x < setup.width; ++x) {
    const float d = UnpackDepth(word2Row[x]);
    Pixel out;
    if (HasGeometry(d)) {
      const glm::vec3 p = ViewPosition(setup, x, y, d);
      const glm::vec3 n = UnpackNormal(word1Row[x], setup.encoding);
      const float invTolerance = 1.0f / (setup.depthTolerance * d);
      const int i0 = x >> 1, i1 = std::min(i0 + (x & 1), setup.halfWidth - 1);
      const float bx0 = (x & 1) ? 0.5f : 1.0f, bx1 = 1.0f - bx0;
      float weightSum = 0.0f, visibilitySum = 0.0f;
      glm::vec3 bounceSum{0.0f};
      for (const auto& [jj, by] : {std::pair{j0, by0}, std::pair{j1, by1}}) {
        if (by == 0.0f) continue;  // an even row's second row: weight 0, which adds nothing
        for (const auto& [ii, bx] : {std::pair{i0, bx0}, std::pair{i1, bx1}}) {
          const size_t at = size_t(jj) * half.stride + size_t(ii);
          const float candidateDepth = half.depth[at];
          float match = 0.0f;
          if (HasGeometry(candidateDepth)) {
            const glm::vec3 c = ViewPosition(setup, 2 * ii, 2 * jj, candidateDepth);
            const glm::vec3 m{half.normal[0][at], half.normal[1][at], half.normal[2][at]};
            match = MatchWeight(p, n, invTolerance, c, m);
          }
          const float weight = (bx * by) * (match + kBounceUpsampleFloor);
          weightSum += weight;
          visibilitySum += weight * half.filteredVisibility[at];
          bounceSum +=
              weight * glm::vec3(half.filteredBounce[0][at], half.filteredBounce[1][at], half.filteredBounce[2][at]);
        }
      }
      out.visibility = visibilitySum / weightSum;
      out.bounce = {bounceSum.x / weightSum, bounceSum.y / weightSum, bounceSum.z / weightSum};
    }
    visibility[x] = out.visibility;
    for (int c = 0; c < 3; ++c) bounce[c][x] = out.bounce[c];
  }
}

namespace {

void ShapePlane(Plane<float>& plane, size_t width, size_t height) {
  if (plane.xsize() != width || plane.ysize() != height) plane = MakePlane<float>(width, height, 0.0f);
}

void ShapePlane3(Plane3<float>& planes, size_t width, size_t height) {
  for (Plane<float>& plane : planes.c) ShapePlane(plane, width, height);
}

}  // namespace

BounceStats RunBounce(const BounceInputs& in, const BounceParams& params, BounceOutputs& out, KernelPath kernels) {
  const Stopwatch total;
  Stopwatch lap;
  const int width = in.gbuffer.width(), height = in.gbuffer.height();
  SSGI_CHECK_EQ(in.view.width, width);
  SSGI_CHECK_EQ(in.view.height, height);
  for (const Plane<float>& plane : in.lit.c) {
    SSGI_CHECK_EQ(plane.xsize(), size_t(width));
    SSGI_CHECK_EQ(plane.ysize(), size_t(height));
  }
  const BounceSetup setup = MakeBounceSetup(in.view, params, in.gbuffer.normalEncoding);
  const size_t halfWidth = size_t(setup.halfWidth), halfHeight = size_t(setup.halfHeight);
  BounceHalfRes& h = out.half;
  ShapePlane(h.depth, halfWidth, halfHeight);
  ShapePlane3(h.normal, halfWidth, halfHeight);
  if (h.normalCode.xsize() != halfWidth || h.normalCode.ysize() != halfHeight)
    h.normalCode = MakePlane<uint32_t>(halfWidth, halfHeight, 0u);
  ShapePlane3(h.lit, halfWidth, halfHeight);
  ShapePlane(h.visibility, halfWidth, halfHeight);
  ShapePlane3(h.bounce, halfWidth, halfHeight);
  ShapePlane(h.horizontalVisibility, halfWidth, halfHeight);
  ShapePlane3(h.horizontalBounce, halfWidth, halfHeight);
  ShapePlane(h.filteredVisibility, halfWidth, halfHeight);
  ShapePlane3(h.filteredBounce, halfWidth, halfHeight);
  ShapePlane(out.visibility, size_t(width), size_t(height));
  ShapePlane3(out.bounce, size_t(width), size_t(height));

  // Planes of one size and type share their row stride (hwy::Image).
  BounceHalfView view{};
  view.stride = size_t(h.depth.PixelsPerRow());
  view.depth = h.depth.ConstRow(0);
  view.normalCode = h.normalCode.ConstRow(0);
  SSGI_CHECK_EQ(size_t(h.normalCode.PixelsPerRow()), view.stride);
  view.filteredVisibility = h.filteredVisibility.ConstRow(0);
  for (int c = 0; c < 3; ++c) {
    view.normal[c] = h.normal.c[c].ConstRow(0);
    view.lit[c] = h.lit.c[c].ConstRow(0);
    view.filteredBounce[c] = h.filteredBounce.c[c].ConstRow(0);
  }
  for (const Plane<float>* plane :
       {&h.normal.c[0], &h.normal.c[1], &h.normal.c[2], &h.lit.c[0], &h.lit.c[1], &h.lit.c[2], &h.visibility,
        &h.bounce.c[0], &h.bounce.c[1], &h.bounce.c[2], &h.horizontalVisibility, &h.horizontalBounce.c[0],
        &h.horizontalBounce.c[1], &h.horizontalBounce.c[2], &h.filteredVisibility, &h.filteredBounce.c[0],
        &h.filteredBounce.c[1], &h.filteredBounce.c[2]})
    SSGI_CHECK_EQ(size_t(plane->PixelsPerRow()), view.stride);

  const bool simd = kernels == KernelPath::kSimd;
  const auto prepareRow = simd ? BouncePrepareRowSimd : BouncePrepareRowScalar;
  const auto marchRow = simd ? BounceMarchRowSimd : BounceMarchRowScalar;
  const auto filterRow = simd ? BounceFilterRowSimd : BounceFilterRowScalar;
  const auto upsampleRow = simd ? BounceUpsampleRowSimd : BounceUpsampleRowScalar;
  const GBuffer& g = in.gbuffer;
  const Plane<uint32_t>& word1 = g.word[GBufferWord::kNormalRoughness];
  const Plane<uint32_t>& word2 = g.word[GBufferWord::kDepth];

  BounceStats stats;
  ParallelForRowBands("bounce.prepare", halfHeight, [&](size_t, size_t yBegin, size_t yEnd) {
    for (size_t j = yBegin; j < yEnd; ++j) {
      const float* litRow[3] = {in.lit.c[0].ConstRow(2 * j), in.lit.c[1].ConstRow(2 * j), in.lit.c[2].ConstRow(2 * j)};
      float* normal[3] = {h.normal.c[0].MutableRow(j), h.normal.c[1].MutableRow(j), h.normal.c[2].MutableRow(j)};
      float* lit[3] = {h.lit.c[0].MutableRow(j), h.lit.c[1].MutableRow(j), h.lit.c[2].MutableRow(j)};
      prepareRow(setup, word1.ConstRow(2 * j), word2.ConstRow(2 * j), litRow, h.depth.MutableRow(j), normal,
                 h.normalCode.MutableRow(j), lit);
    }
  });
  stats.prepareMs = lap.Lap();

  std::vector<uint64_t> bandTaps(RowBandCount(halfHeight), 0);
  ParallelForRowBands("bounce.march", halfHeight, [&](size_t band, size_t yBegin, size_t yEnd) {
    for (size_t j = yBegin; j < yEnd; ++j) {
      float* bounce[3] = {h.bounce.c[0].MutableRow(j), h.bounce.c[1].MutableRow(j), h.bounce.c[2].MutableRow(j)};
      bandTaps[band] += marchRow(setup, view, int(j), h.visibility.MutableRow(j), bounce);
    }
  });
  for (const uint64_t taps : bandTaps) stats.taps += taps;
  stats.marchMs = lap.Lap();

  // The filter's two passes: along rows, then along columns.
  const auto filterPass = [&](const char* name, bool vertical, const Plane<float>& sourceVisibility,
                              const Plane3<float>& sourceBounce, Plane<float>& visibility, Plane3<float>& bounce) {
    const float* sourceBounceRows[3] = {sourceBounce.c[0].ConstRow(0), sourceBounce.c[1].ConstRow(0),
                                        sourceBounce.c[2].ConstRow(0)};
    ParallelForRowBands(name, halfHeight, [&](size_t, size_t yBegin, size_t yEnd) {
      for (size_t j = yBegin; j < yEnd; ++j) {
        float* bounceRows[3] = {bounce.c[0].MutableRow(j), bounce.c[1].MutableRow(j), bounce.c[2].MutableRow(j)};
        filterRow(setup, view, int(j), vertical, sourceVisibility.ConstRow(0), sourceBounceRows,
                  visibility.MutableRow(j), bounceRows);
      }
    });
  };
  filterPass("bounce.filter_rows", false, h.visibility, h.bounce, h.horizontalVisibility, h.horizontalBounce);
  filterPass("bounce.filter_columns", true, h.horizontalVisibility, h.horizontalBounce, h.filteredVisibility,
             h.filteredBounce);
  stats.filterMs = lap.Lap();

  ParallelForRowBands("bounce.upsample", size_t(height), [&](size_t, size_t yBegin, size_t yEnd) {
    for (size_t y = yBegin; y < yEnd; ++y) {
      float* bounce[3] = {out.bounce.c[0].MutableRow(y), out.bounce.c[1].MutableRow(y), out.bounce.c[2].MutableRow(y)};
      upsampleRow(setup, view, int(y), word1.ConstRow(y), word2.ConstRow(y), out.visibility.MutableRow(y), bounce);
    }
  });
  stats.upsampleMs = lap.Lap();
  stats.pixels = size_t(width) * size_t(height);
  stats.ms = total.Milliseconds();
  return stats;
}

}  // namespace ssgi
