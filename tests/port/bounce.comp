// Diffuse bounce and ambient occlusion by the visibility bitmask (docs/pipeline.md §Diffuse bounce
// and ambient occlusion (visibility bitmask)). One stage per dispatch: prepare (the half-resolution
// inputs at pixel (2i, 2j)), the march (per half-resolution pixel, the slices' sector masks), the
// filter along rows, the filter along columns, the upsample to full resolution. Buffers of several
// channels hold them as planes one after the other.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Word1 { uint word1[]; };
layout(std430, binding = 1) readonly buffer Word2 { float depth[]; };
layout(std430, binding = 2) readonly buffer Lit { float lit[]; };  // three planes, full resolution
// The half-resolution inputs: prepare writes them, the later stages read them.
layout(std430, binding = 3) buffer HalfDepth { float halfDepth[]; };  // +inf without geometry
layout(std430, binding = 4) buffer HalfNormal { float halfNormal[]; };  // three planes
layout(std430, binding = 5) buffer HalfNormalCode { uint halfNormalCode[]; };
layout(std430, binding = 6) buffer HalfLit { float halfLit[]; };  // three planes
// What the filter and the upsample read (the march's, the rows', the filtered), half resolution.
layout(std430, binding = 7) readonly buffer SourceVisibility { float sourceVisibility[]; };
layout(std430, binding = 8) readonly buffer SourceBounce { float sourceBounce[]; };  // three planes
// What the march, the filter and the upsample write (the upsample at full resolution).
layout(std430, binding = 9) writeonly buffer Visibility { float visibility[]; };
layout(std430, binding = 10) writeonly buffer Bounce { float bounce[]; };  // three planes
// The direction table, (x, y) at [16 k + r]: angle pi (k + (r + 0.5) / 16) / slices in double, its
// cos and sin rounded once (by the runner, as the spec says a port does).
layout(std430, binding = 11) readonly buffer Directions { vec2 directions[]; };

const int kPrepare = 0;
const int kMarch = 1;
const int kFilterRows = 2;
const int kFilterColumns = 3;
const int kUpsample = 4;
uniform int stage;
uniform ivec2 halfSize;  // ((W + 1) / 2, (H + 1) / 2)
// BounceParams.
uniform int slices;
uniform int steps;
uniform int sectors;
uniform float radius;
uniform float maxRadiusPixels;
uniform float thickness;
uniform float depthTolerance;

// The spec's constants by their float32 bit patterns: a decimal literal is the compiler's to round.
const float kHalfPi = uintBitsToFloat(0x3FC90FDBu);
const float kPi = uintBitsToFloat(0x40490FDBu);
const float kMinDepth = uintBitsToFloat(0x358637BDu);  // 1e-6
const float kMaxDepth = uintBitsToFloat(0x49742400u);  // 1e6
const float kMinTapDistance = uintBitsToFloat(0x3FA66666u);  // 1.3
const float kMinRiseInverseSquare = 128.0;
const float kUpsampleFloor = uintBitsToFloat(0x3A83126Fu);  // 0.001
const float kOct24Scale = uintBitsToFloat(0x3A000801u);  // 2 / 4095
const float kXyz8Scale = uintBitsToFloat(0x3C008081u);  // 2 / 255
const float kAcosA0 = uintBitsToFloat(0x3FC90DA4u);
const float kAcosA1 = uintBitsToFloat(0xBE593484u);
const float kAcosA2 = uintBitsToFloat(0x3D981627u);
const float kAcosA3 = uintBitsToFloat(0xBC996E30u);
const int kFilterRadius = 3;
const float kFilterSpatial[7] = float[7](1.0, 2.0, 3.0, 4.0, 3.0, 2.0, 1.0);

// std::min, std::max and std::clamp as the spec means them: GLSL leaves min/max of a NaN (and which
// zero of -0 and +0) to the implementation; std:: returns the first operand unless the comparison
// holds.
float StdMin(float a, float b) { return b < a ? b : a; }
float StdMax(float a, float b) { return a < b ? b : a; }
float StdClamp(float v, float lo, float hi) { return v < lo ? lo : (hi < v ? hi : v); }

bool HasGeometry(float d) { return d >= kMinDepth && d <= kMaxDepth; }

// AcosPoly (core/fast_math.h): Hastings' cubic times sqrt(1 - |x|), each product and sum rounded.
float AcosPoly(float x) {
  precise float a = abs(x);
  precise float p = kAcosA3 * a + kAcosA2;
  p = p * a + kAcosA1;
  p = p * a + kAcosA0;
  precise float r = p * sqrt(1.0 - a);
  precise float result = x < 0.0 ? kPi - r : r;
  return result;
}

// The view ray (z = -1) through full-resolution image position (x + 0.5, y + 0.5), as a linear
// function of the position with the set-up's scales and offsets.
vec3 Ray(float x, float y) {
  precise float scaleX = (2.0 * tanHalf.x) / float(imageSize.x);
  precise float scaleY = -((2.0 * tanHalf.y) / float(imageSize.y));
  precise float rx = (x + 0.5) * scaleX + -tanHalf.x;
  precise float ry = (y + 0.5) * scaleY + tanHalf.y;
  return vec3(rx, ry, -1.0);
}

// The point at depth d on the centre ray of full-resolution pixel (x, y).
vec3 ViewPosition(int x, int y, float d) {
  precise vec3 p = d * Ray(float(x), float(y));
  return p;
}

// A normal code's direction without its length: one product per component, folded as the decode
// folds it.
vec3 RawNormal(uint code) {
  if (normalEncoding == kNormalXyz8) {
    precise vec3 n = vec3(float(code & 0xFFu), float((code >> 8) & 0xFFu), float((code >> 16) & 0xFFu)) * kXyz8Scale -
                     1.0;
    return n;
  }
  precise float x = float(code & 0xFFFu) * kOct24Scale - 1.0;
  precise float y = float((code >> 12) & 0xFFFu) * kOct24Scale - 1.0;
  precise float z = (1.0 - abs(x)) - abs(y);
  precise float fold = StdMax(-z, 0.0);
  x = x >= 0.0 ? x - fold : x + fold;
  y = y >= 0.0 ? y - fold : y + fold;
  return vec3(x, y, z);
}

// Bits 0 .. k - 1 set, k in [0, 32] (a shift by 32 is undefined in GLSL, as in C++).
uint Below(int k) { return k >= 32 ? 0xFFFFFFFFu : (1u << uint(k)) - 1u; }

// The sectors whose centres (k + 0.5) / N lie in [lo, hi]; int() truncates, as C++'s.
uint SectorMask(float lo, float hi) {
  const float n = float(sectors);
  precise float start = lo * n + 0.5;
  precise float end = hi * n + 0.5;
  return Below(int(end)) & ~Below(int(start));
}

// One slice of a pixel: its frame in the slice plane and its cosine-weighted sector map.
struct Slice {
  vec3 o;  // unit, in the slice plane, perpendicular to v
  float cosGamma, sinGamma, halfCos, halfSin, q0, invI;
  float weight;  // 0: the slice is skipped
};

Slice MakeSlice(vec3 v, vec3 n, float cx, float cy) {
  Slice s;
  precise float dv = cx * v.x - cy * v.y;
  precise vec3 along = vec3(cx - dv * v.x, -cy - dv * v.y, -(dv * v.z));
  precise float invAlong = 1.0 / sqrt(Dot3(along, along));
  precise vec3 o = along * invAlong;
  s.o = o;
  const float no = Dot3(n, o), nv = Dot3(n, v);
  precise float projected = sqrt(no * no + nv * nv);
  const bool facing = nv > 0.0 && projected > 0.0;
  precise float cosGamma = facing ? nv / projected : 0.0;
  precise float sinGamma = facing ? no / projected : (no < 0.0 ? -1.0 : 1.0);
  const float absGamma = AcosPoly(cosGamma);
  const float gamma = sinGamma < 0.0 ? -absGamma : absGamma;
  precise float halfCos = 0.5 * cosGamma;
  precise float halfSin = 0.5 * sinGamma;
  precise float measure = cosGamma + gamma * sinGamma;
  precise float invI = 1.0 / measure;
  precise float q0 = (cosGamma + (gamma - kHalfPi) * sinGamma) * -0.5;
  precise float weight = projected > 0.0 ? projected * measure : 0.0;
  s.cosGamma = cosGamma;
  s.sinGamma = sinGamma;
  s.halfCos = halfCos;
  s.halfSin = halfSin;
  s.q0 = q0;
  s.invI = invI;
  s.weight = weight;
  return s;
}

// Where direction (x, y) of the slice plane on side `positive` falls in the slice's cosine-weighted
// measure, 0 .. 1; below the tangent plane, the end of its side.
float SectorPosition(Slice s, float x, float y, bool positive) {
  precise float length = sqrt(x * x + y * y);
  precise float inv = 1.0 / length;
  precise float c = StdClamp(y * inv, -1.0, 1.0);
  precise float a = abs(x) * inv;
  const float theta = AcosPoly(c);
  precise float sideCos = s.halfCos * (a * a);
  precise float q = (positive ? sideCos : -sideCos) + s.halfSin * (theta - c * a);
  const float sideSin = positive ? a : -a;
  precise float below = c * s.cosGamma + sideSin * s.sinGamma;
  if (below < 0.0) return positive ? 1.0 : 0.0;
  precise float u = StdClamp((q - s.q0) * s.invI, 0.0, 1.0);
  return u;
}

int HalfIndex(int i, int j) { return j * halfSize.x + i; }
vec3 HalfNormalAt(int at) {
  const int plane = halfSize.x * halfSize.y;
  return vec3(halfNormal[at], halfNormal[at + plane], halfNormal[at + 2 * plane]);
}
vec3 HalfLitAt(int at) {
  const int plane = halfSize.x * halfSize.y;
  return vec3(halfLit[at], halfLit[at + plane], halfLit[at + 2 * plane]);
}
vec3 SourceBounceAt(int at) {
  const int plane = halfSize.x * halfSize.y;
  return vec3(sourceBounce[at], sourceBounce[at + plane], sourceBounce[at + 2 * plane]);
}

// The outputs at index `at` of planes of `pixels` each.
void Store(int at, int pixels, float v, vec3 b) {
  visibility[at] = v;
  for (int c = 0; c < 3; ++c) bounce[at + c * pixels] = b[c];
}

// The 4x4 Bayer matrix: the rotation phase of half-resolution pixel (i, j).
const int kBayer[16] = int[16](0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5);

void Prepare(int i, int j) {
  const int x = 2 * i, y = 2 * j;
  const int source = y * imageSize.x + x, at = HalfIndex(i, j);
  const int fullPlane = imageSize.x * imageSize.y, plane = halfSize.x * halfSize.y;
  const float d = depth[source];
  const bool geometry = HasGeometry(d);
  halfDepth[at] = geometry ? d : kBackgroundDepth;
  const vec3 n = geometry ? UnpackNormal(word1[source]) : vec3(0.0);
  halfNormalCode[at] = geometry ? word1[source] & 0xFFFFFFu : 0u;
  for (int c = 0; c < 3; ++c) {
    halfNormal[at + c * plane] = n[c];
    halfLit[at + c * plane] = SanitizeRadiance(lit[source + c * fullPlane]);
  }
}

void March(int i, int j) {
  const int centre = HalfIndex(i, j), plane = halfSize.x * halfSize.y;
  const float d = halfDepth[centre];
  if (!HasGeometry(d)) {
    Store(centre, plane, 1.0, vec3(0.0));
    return;
  }
  const vec3 n = HalfNormalAt(centre);
  const vec3 p = ViewPosition(2 * i, 2 * j, d);
  precise float invLength = 1.0 / sqrt(Dot3(p, p));
  precise vec3 v = vec3(-(p.x * invLength), -(p.y * invLength), -(p.z * invLength));
  // radiusPixelsAtUnitDepth = radius (H / (2 halfY)), in full-resolution pixels.
  precise float radiusPixelsAtUnitDepth = radius * (float(imageSize.y) / (2.0 * tanHalf.y));
  precise float reach = StdMin(radiusPixelsAtUnitDepth / d, maxRadiusPixels) * 0.5;
  const int rotation = kBayer[(j & 3) * 4 + (i & 3)];
  const int jitter = (5 * rotation) & 15;
  const float sectorCount = float(sectors);

  precise float weightSum = 0.0, visibilitySum = 0.0;
  precise vec3 bounceSum = vec3(0.0);
  for (int k = 0; k < slices; ++k) {
    const float cx = directions[16 * k + rotation].x;
    const float cy = directions[16 * k + rotation].y;
    const Slice slice = MakeSlice(v, n, cx, cy);
    if (!(slice.weight > 0.0)) continue;
    uint occluded = 0u;
    precise vec3 sliceBounce = vec3(0.0);
    for (int step = 0; step < steps; ++step) {
      // stepSpread[16 step + q]: the square of the step's rank.
      precise float rank = (float(step) + (float(jitter) + 0.5) / 16.0) / float(steps);
      precise float spread = rank * rank;
      precise float distance = kMinTapDistance + spread * reach;
      precise float offsetX = distance * cx, offsetY = distance * cy;
      for (int side = 0; side < 2; ++side) {
        const bool positive = side == 0;
        const float sx = positive ? offsetX : -offsetX, sy = positive ? offsetY : -offsetY;
        // The sample lies on the slice's screen line; the pixel read is the nearest one.
        precise float lineX = float(i) + sx, lineY = float(j) + sy;
        precise float tx = float(i) + floor(sx + 0.5), ty = float(j) + floor(sy + 0.5);
        if (!(tx >= 0.0 && tx < float(halfSize.x) && ty >= 0.0 && ty < float(halfSize.y))) continue;
        const int tap = HalfIndex(int(tx), int(ty));
        const float tapDepth = halfDepth[tap];
        if (!HasGeometry(tapDepth)) continue;
        const vec3 pixelRay = Ray(2.0 * tx, 2.0 * ty);
        precise vec3 own = tapDepth * pixelRay - p;
        const float rise = Dot3(n, own);
        precise float riseTest = (rise * rise) * kMinRiseInverseSquare;
        if (!(rise > 0.0) || riseTest <= Dot3(own, own)) continue;
        const vec3 tapNormal = RawNormal(halfNormalCode[tap]);
        const vec3 lineRay = Ray(2.0 * lineX, 2.0 * lineY);
        precise float ratio = Dot3(tapNormal, pixelRay) / Dot3(tapNormal, lineRay);
        const bool onPlane = ratio >= 0.5 && ratio <= 2.0;
        precise float scale = tapDepth * ratio;
        precise vec3 point = onPlane ? scale * lineRay : tapDepth * pixelRay;
        precise vec3 delta = point - p;
        const float x = Dot3(delta, slice.o), y = Dot3(delta, v);
        if (x == 0.0 && y == 0.0) continue;
        const float front = SectorPosition(slice, x, y, positive);
        precise float backY = y - thickness;
        const float back = SectorPosition(slice, x, backY, positive);
        const uint mask = SectorMask(StdMin(front, back), StdMax(front, back));
        const uint fresh = mask & ~occluded;
        occluded |= mask;
        if (fresh == 0u) continue;
        // Only a surface that faces the pixel sends it light.
        if (!(Dot3(tapNormal, delta) < 0.0)) continue;
        const float count = float(bitCount(fresh));
        precise vec3 arriving = count * HalfLitAt(tap);
        sliceBounce = sliceBounce + arriving;
      }
    }
    weightSum = weightSum + slice.weight;
    precise float open = 1.0 - float(bitCount(occluded)) / sectorCount;
    visibilitySum = visibilitySum + slice.weight * open;
    bounceSum = bounceSum + slice.weight * sliceBounce;
  }
  if (!(weightSum > 0.0)) {
    Store(centre, plane, 1.0, vec3(0.0));
    return;
  }
  precise float meanVisibility = visibilitySum / weightSum;
  precise float norm = weightSum * sectorCount;
  precise vec3 meanBounce = bounceSum / norm;
  Store(centre, plane, meanVisibility, meanBounce);
}

// The weight of a neighbour at view position c with unit normal m for a pixel at p with unit normal
// n: linear in its distance from the pixel's tangent plane, times max(n.m, 0)^8.
float MatchWeight(vec3 p, vec3 n, float invTolerance, vec3 c, vec3 m) {
  precise vec3 offset = c - p;
  precise float plane = StdMax(0.0, 1.0 - abs(Dot3(n, offset)) * invTolerance);
  const float facing = StdMax(0.0, Dot3(n, m));
  precise float f2 = facing * facing;
  precise float f4 = f2 * f2;
  precise float weight = plane * (f4 * f4);
  return weight;
}

void Filter(int i, int j, bool vertical) {
  const int centre = HalfIndex(i, j), plane = halfSize.x * halfSize.y;
  const float d = halfDepth[centre];
  if (!HasGeometry(d)) {
    Store(centre, plane, 1.0, vec3(0.0));
    return;
  }
  const vec3 p = ViewPosition(2 * i, 2 * j, d);
  const vec3 n = HalfNormalAt(centre);
  precise float invTolerance = 1.0 / (depthTolerance * d);
  precise float weightSum = 0.0, visibilitySum = 0.0;
  precise vec3 bounceSum = vec3(0.0);
  for (int t = -kFilterRadius; t <= kFilterRadius; ++t) {
    const int ii = vertical ? i : i + t, jj = vertical ? j + t : j;
    precise float weight = 0.0;
    float value = 0.0;
    vec3 b = vec3(0.0);
    if (ii >= 0 && ii < halfSize.x && jj >= 0 && jj < halfSize.y) {
      const int at = HalfIndex(ii, jj);
      const float neighbourDepth = halfDepth[at];
      if (HasGeometry(neighbourDepth)) {
        const vec3 c = ViewPosition(2 * ii, 2 * jj, neighbourDepth);
        weight = kFilterSpatial[t + kFilterRadius] * MatchWeight(p, n, invTolerance, c, HalfNormalAt(at));
        value = sourceVisibility[at];
        b = SourceBounceAt(at);
      }
    }
    weightSum = weightSum + weight;
    visibilitySum = visibilitySum + weight * value;
    bounceSum = bounceSum + weight * b;
  }
  precise float meanVisibility = visibilitySum / weightSum;
  precise vec3 meanBounce = bounceSum / weightSum;
  Store(centre, plane, meanVisibility, meanBounce);
}

void Upsample(int x, int y) {
  const int index = y * imageSize.x + x, pixels = imageSize.x * imageSize.y;
  const float d = depth[index];
  if (!HasGeometry(d)) {
    Store(index, pixels, 1.0, vec3(0.0));
    return;
  }
  const vec3 p = ViewPosition(x, y, d);
  const vec3 n = UnpackNormal(word1[index]);
  precise float invTolerance = 1.0 / (depthTolerance * d);
  const int i0 = x >> 1, i1 = min(i0 + (x & 1), halfSize.x - 1);
  const int j0 = y >> 1, j1 = min(j0 + (y & 1), halfSize.y - 1);
  precise float bx0 = (x & 1) != 0 ? 0.5 : 1.0, bx1 = 1.0 - bx0;
  precise float by0 = (y & 1) != 0 ? 0.5 : 1.0, by1 = 1.0 - by0;
  precise float weightSum = 0.0, visibilitySum = 0.0;
  precise vec3 bounceSum = vec3(0.0);
  for (int row = 0; row < 2; ++row) {
    const int jj = row == 0 ? j0 : j1;
    const float by = row == 0 ? by0 : by1;
    if (by == 0.0) continue;  // an even row's second row: weight 0, which adds nothing
    for (int column = 0; column < 2; ++column) {
      const int ii = column == 0 ? i0 : i1;
      const float bx = column == 0 ? bx0 : bx1;
      const int at = HalfIndex(ii, jj);
      const float candidateDepth = halfDepth[at];
      float match = 0.0;
      if (HasGeometry(candidateDepth))
        match = MatchWeight(p, n, invTolerance, ViewPosition(2 * ii, 2 * jj, candidateDepth), HalfNormalAt(at));
      precise float weight = (bx * by) * (match + kUpsampleFloor);
      weightSum = weightSum + weight;
      visibilitySum = visibilitySum + weight * sourceVisibility[at];
      bounceSum = bounceSum + weight * SourceBounceAt(at);
    }
  }
  precise float meanVisibility = visibilitySum / weightSum;
  precise vec3 meanBounce = bounceSum / weightSum;
  Store(index, pixels, meanVisibility, meanBounce);
}

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  const ivec2 size = stage == kUpsample ? imageSize : halfSize;
  if (pixel.x >= size.x || pixel.y >= size.y) return;
  if (stage == kPrepare) {
    Prepare(pixel.x, pixel.y);
  } else if (stage == kMarch) {
    March(pixel.x, pixel.y);
  } else if (stage == kFilterRows || stage == kFilterColumns) {
    Filter(pixel.x, pixel.y, stage == kFilterColumns);
  } else {
    Upsample(pixel.x, pixel.y);
  }
}
