// SSR Hi-Z trace (docs/pipeline.md §SSR: Hi-Z trace; Uludag, GPU Pro 5, with the Bitsquid and
// FidelityFX SSSR fixes): per pixel, the view ray reflected about the normal, marched in screen
// space (x, y, 1/d) through the Hi-Z max pyramid of inverse depth.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Word1 { uint word1[]; };
layout(std430, binding = 1) readonly buffer Word2 { float depth[]; };
// Every level of the Hi-Z, one after the other.
layout(std430, binding = 2) readonly buffer HiZ { float hiz[]; };
layout(std430, binding = 3) writeonly buffer HitX { float hitX[]; };
layout(std430, binding = 4) writeonly buffer HitY { float hitY[]; };
layout(std430, binding = 5) writeonly buffer Confidence { float confidence[]; };
layout(std430, binding = 6) writeonly buffer Iterations { float iterations[]; };

const int kMaxLevels = 16;  // a 16384-pixel side has 15 levels
uniform int levelCount;
uniform ivec2 levelSizes[kMaxLevels];
uniform int levelOffsets[kMaxLevels];  // in floats, into `hiz`

uniform float nearPlane;
uniform int maxIterations;
uniform int startLevel;
uniform float roughnessCutoff;
uniform float thickness;
uniform float edgeFade;
uniform float towardCameraFade;
uniform float quadRoughness;
uniform float blockRoughness;

const float kNever = 1e30;          // a "never" t that stays finite
const float kTinyComponent = 1e-20; // direction components below this have no reciprocal
const float kNudge = 1.0 / 64.0;    // px past a crossed cell boundary
const float kMaxCoordinate = 32768.0;
const float kMaxRayLengthInDepths = 1000.0;
// Shared rays: one surface means depths within 1/16 of the source's and normal codes within these
// steps per axis.
const float kSharedRayDepthTolerance = 1.0 / 16.0;
const int kSharedRayStepsOct24 = 96;
const int kSharedRayStepsXyz8 = 6;

float SafeReciprocal(float v) {
  precise float reciprocal = 1.0 / v;
  return abs(v) < kTinyComponent ? kNever : reciprocal;
}

// The cell of level-0 coordinate p on a level of `size` cells of 2^level px; the last cell also
// covers what the floor-halved size leaves over.
int CellIndex(float p, int level, int size) {
  const int pixel = int(clamp(p, 0.0, kMaxCoordinate));
  return min(pixel >> level, size - 1);
}

// The boundary the ray leaves cell `cell` through: upper for a positive (or zero) direction, lower
// for a negative one; the last cell's upper boundary is the image border.
float CellBoundary(int cell, int level, int size, int imageSide, bool positive) {
  if (!positive) return float(cell << level);
  return cell + 1 == size ? float(imageSide) : float((cell + 1) << level);
}

bool InsideImage(vec3 p) { return p.x >= 0.0 && p.x < float(imageSize.x) && p.y >= 0.0 && p.y < float(imageSize.y); }

// View-space point in front of the camera -> (x, y, 1/d).
vec3 Project(vec3 q) {
  precise float d = -q.z;
  precise float ndcX = q.x / (d * tanHalf.x);
  precise float ndcY = q.y / (d * tanHalf.y);
  precise vec3 projected =
      vec3((ndcX * 0.5 + 0.5) * float(imageSize.x), (0.5 - ndcY * 0.5) * float(imageSize.y), 1.0 / d);
  return projected;
}

struct March {
  bool hit;
  vec3 position;
  int iterations;
};

March MarchHiZ(vec3 origin, vec3 end) {
  March result = March(false, origin, 0);
  if (any(isinf(end)) || any(isnan(end))) return result;
  const int topLevel = levelCount - 1;
  // Snap the origin strictly inside its level-0 cell: its first crossing leaves that cell.
  precise vec3 pos = origin;
  const int startX = CellIndex(pos.x, 0, imageSize.x);
  const int startY = CellIndex(pos.y, 0, imageSize.y);
  pos.x = clamp(pos.x, float(startX) + kNudge, float(startX + 1) - kNudge);
  pos.y = clamp(pos.y, float(startY) + kNudge, float(startY + 1) - kNudge);
  result.position = pos;

  precise vec3 dir = end - pos;
  const vec3 inv = vec3(SafeReciprocal(dir.x), SafeReciprocal(dir.y), SafeReciprocal(dir.z));
  const bool positiveX = !(dir.x <= -kTinyComponent);
  const bool positiveY = !(dir.y <= -kTinyComponent);
  precise float exitX = ((positiveX ? float(imageSize.x) : 0.0) - pos.x) * inv.x;
  precise float exitY = ((positiveY ? float(imageSize.y) : 0.0) - pos.y) * inv.y;
  const float tEnd = min(1.0, min(exitX, exitY));

  precise float t = 0.0;
  int level = 0;
  bool skipOrigin = true;  // the first step only leaves the origin's cell: it holds the reflector
  while (result.iterations < maxIterations) {
    ++result.iterations;
    const ivec2 size = levelSizes[level];
    const int cellX = CellIndex(pos.x, level, size.x);
    const int cellY = CellIndex(pos.y, level, size.y);
    const float closest = hiz[levelOffsets[level] + cellY * size.x + cellX];

    const float boundaryX = CellBoundary(cellX, level, size.x, imageSize.x, positiveX);
    const float boundaryY = CellBoundary(cellY, level, size.y, imageSize.y, positiveY);
    precise float tX = (boundaryX - pos.x) * inv.x;
    precise float tY = (boundaryY - pos.y) * inv.y;
    const float tCell = min(tX, tY);
    precise float tDepth = kNever;
    if (!skipOrigin) {
      if (pos.z <= closest) tDepth = 0.0;
      else if (dir.z <= -kTinyComponent) tDepth = (closest - pos.z) * inv.z;
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
      if (tX <= tY) pos.x = boundaryX + (positiveX ? kNudge : -kNudge);
      else pos.y = boundaryY + (positiveY ? kNudge : -kNudge);
      result.position = pos;
      if (!InsideImage(pos)) return result;
      level = min(result.iterations == 1 ? startLevel : level + 1, topLevel);
    }
  }
  return result;
}

float EdgeFade(float p, float size) {
  if (!(edgeFade > 0.0)) return 1.0;
  precise float fade = clamp(min(p, size - p) / (edgeFade * size), 0.0, 1.0);
  return fade;
}

bool Traces(int index) {
  const float d = depth[index];
  return d < kBackgroundDepth && d > 0.0 && UnpackRoughness(word1[index]) < roughnessCutoff;
}

bool NormalCodesClose(uint a, uint b) {
  const bool xyz8 = normalEncoding == kNormalXyz8;
  const int fields = xyz8 ? 3 : 2, bits = xyz8 ? 8 : 12;
  const uint mask = (1u << bits) - 1u;
  const int steps = xyz8 ? kSharedRayStepsXyz8 : kSharedRayStepsOct24;
  for (int k = 0; k < fields; ++k) {
    if (abs(int((a >> (k * bits)) & mask) - int((b >> (k * bits)) & mask)) > steps) return false;
  }
  return true;
}

// Whether `pixel` takes the ray of the top-left pixel of its cell (mask ~1: 2x2 quad, ~3: 4x4 block).
bool SharesRay(ivec2 pixel, int mask, float threshold) {
  const ivec2 source = pixel & ivec2(mask);
  if (source == pixel) return false;
  const int own = pixel.y * imageSize.x + pixel.x;
  const int other = source.y * imageSize.x + source.x;
  if (!Traces(own) || !Traces(other)) return false;
  if (!(UnpackRoughness(word1[own]) >= threshold) || !(UnpackRoughness(word1[other]) >= threshold)) return false;
  precise float gap = abs(depth[own] - depth[other]);
  precise float tolerance = kSharedRayDepthTolerance * depth[other];
  return gap <= tolerance && NormalCodesClose(word1[own], word1[other]);
}

// The pixel whose ray `pixel` takes (docs/pipeline.md §SSR: Hi-Z trace, "Shared rays").
ivec2 RaySource(ivec2 pixel) {
  if (SharesRay(pixel, ~3, blockRoughness)) return pixel & ivec2(~3);
  if (SharesRay(pixel, ~1, quadRoughness)) return pixel & ivec2(~1);
  return pixel;
}

void main() {
  const ivec2 own = ivec2(gl_GlobalInvocationID.xy);
  if (own.x >= imageSize.x || own.y >= imageSize.y) return;
  const int ownIndex = own.y * imageSize.x + own.x;
  // Untraced pixels, misses and rejected hits.
  hitX[ownIndex] = -1.0;
  hitY[ownIndex] = -1.0;
  confidence[ownIndex] = 0.0;
  iterations[ownIndex] = 0.0;
  if (!Traces(ownIndex)) return;

  // A quad's source may itself take its block's ray: two hops at most. The oracle traces the
  // source once and copies; here each invocation traces its source's ray again, the same bits.
  const ivec2 pixel = RaySource(RaySource(own));
  const bool sharedRay = pixel != own;
  const int index = pixel.y * imageSize.x + pixel.x;
  const float d = depth[index];
  const uint w1 = word1[index];

  const vec2 centre = vec2(pixel) + 0.5;
  precise vec3 p = PixelRayDirection(centre) * d;
  const vec3 n = UnpackNormal(w1);
  precise vec3 v = p / sqrt(Dot3(p, p));
  precise vec3 r = v - 2.0 * Dot3(v, n) * n;
  // Rays toward the camera: the max pyramid has no back side, so they fade out.
  precise float towardCamera = r.z <= 0.0 ? 1.0 : 1.0 - r.z / towardCameraFade;
  if (!(towardCamera > 0.0)) return;

  // Near-plane clip before projecting: the end's view depth d - r.z L stays >= near.
  precise float rayLength = kMaxRayLengthInDepths * d;
  if (r.z > 0.0) rayLength = min(rayLength, (d - nearPlane) / r.z);
  if (!(rayLength > 0.0)) return;
  precise vec3 q = p + r * rayLength;
  if (!(-q.z > 0.0)) return;

  precise float inverseDepth = 1.0 / d;
  const March march = MarchHiZ(vec3(centre, inverseDepth), Project(q));
  if (!sharedRay) iterations[ownIndex] = float(march.iterations);
  const vec3 at = march.position;
  if (!march.hit || !InsideImage(at) || !(at.z > 0.0)) return;

  const int hx = min(int(at.x), imageSize.x - 1);
  const int hy = min(int(at.y), imageSize.y - 1);
  const int hitIndex = hy * imageSize.x + hx;
  const float hitDepth = depth[hitIndex];
  if (!(hitDepth < kBackgroundDepth)) return;
  // Back faces and surfaces the ray only grazes cannot reflect light back along r.
  if (Dot3(UnpackNormal(word1[hitIndex]), r) >= 0.0) return;

  // Relative depth excess of the ray over the surface.
  precise float excess = (1.0 / at.z) / hitDepth - 1.0;
  precise float thick = clamp(2.0 - excess / thickness, 0.0, 1.0);
  precise float trust = thick * towardCamera * EdgeFade(at.x, float(imageSize.x)) * EdgeFade(at.y, float(imageSize.y));
  if (!(trust > 0.0)) return;
  hitX[ownIndex] = at.x;
  hitY[ownIndex] = at.y;
  confidence[ownIndex] = min(trust, 1.0);
}
