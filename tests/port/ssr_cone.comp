// SSR cone trace (docs/pipeline.md §SSR: cone trace, after Uludag, GPU Pro 5): the reflected
// radiance of each pixel the trace hit, gathered from the colour pyramid along a cone from the hit
// back toward the pixel. 0 where the trace's confidence is 0.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Word1 { uint word1[]; };
layout(std430, binding = 1) readonly buffer HitX { float hitX[]; };
layout(std430, binding = 2) readonly buffer HitY { float hitY[]; };
layout(std430, binding = 3) readonly buffer Confidence { float confidence[]; };
// Every level of the colour pyramid, one after the other, each three planes (R, G, B).
layout(std430, binding = 4) readonly buffer Pyramid { float pyramid[]; };
layout(std430, binding = 5) writeonly buffer Reflected { float reflected[]; };  // three planes

const int kMaxLevels = 16;  // a 16384-pixel side has 15 levels
uniform int levelCount;
uniform ivec2 levelSizes[kMaxLevels];
uniform int levelOffsets[kMaxLevels];  // in floats, into `pyramid`
// tan(theta) of the cone's half-angle per roughness code, made by the runner (§SSR: cone trace).
uniform float coneTan[256];
uniform int maxSamples;

// Bilinear fetch of level `level` at the level-0 position `position`, clamp to edge.
vec3 SampleLevel(int level, vec2 position) {
  const ivec2 size = levelSizes[level];
  precise vec2 scaled = position * (vec2(size) / vec2(imageSize)) - 0.5;
  const vec2 floorScaled = floor(scaled);
  precise vec2 f = scaled - floorScaled;
  const ivec2 i0 = clamp(ivec2(floorScaled), ivec2(0), size - 1);
  const ivec2 i1 = clamp(ivec2(floorScaled) + 1, ivec2(0), size - 1);
  precise vec3 texels[4];
  const ivec2 corners[4] = ivec2[4](i0, ivec2(i1.x, i0.y), ivec2(i0.x, i1.y), i1);
  for (int i = 0; i < 4; ++i) {
    const int base = levelOffsets[level] + corners[i].y * size.x + corners[i].x;
    const int plane = size.x * size.y;
    texels[i] = vec3(pyramid[base], pyramid[base + plane], pyramid[base + 2 * plane]);
  }
  precise vec3 top = texels[0] + (texels[1] - texels[0]) * f.x;
  precise vec3 bottom = texels[2] + (texels[3] - texels[2]) * f.x;
  precise vec3 value = top + (bottom - top) * f.y;
  return value;
}

// Trilinear fetch for a circle of `diameter` px (>= 1) at level log2(diameter), log2 piecewise
// linear between powers of two: diameter = m 2^e (frexp, m in [0.5, 1)) is between levels e - 1
// and e, at fraction 2m - 1. Levels past the last read the last.
vec3 SampleCircle(vec2 position, float diameter) {
  int exponent;
  const float mantissa = frexp(diameter, exponent);
  const int level = exponent - 1;
  if (level >= levelCount - 1) return SampleLevel(levelCount - 1, position);
  precise float f = 2.0 * mantissa - 1.0;
  const vec3 fine = SampleLevel(level, position);
  const vec3 coarse = SampleLevel(level + 1, position);
  precise vec3 value = fine + (coarse - fine) * f;
  return value;
}

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;
  const int index = pixel.y * imageSize.x + pixel.x;
  const int plane = imageSize.x * imageSize.y;
  precise vec3 radiance = vec3(0.0);
  if (confidence[index] > 0.0) {
    const uint code = word1[index] >> 24;
    const vec2 hit = vec2(hitX[index], hitY[index]);
    const vec2 origin = vec2(pixel) + 0.5;
    precise vec2 toHit = hit - origin;
    precise float h = sqrt(toHit.x * toHit.x + toHit.y * toHit.y);
    if (code == 0u || h < 0.5) {
      radiance = SampleLevel(0, hit);
    } else {
      const float t = coneTan[code];
      // The incircle's radius per unit height of the triangle it is inscribed in.
      precise float inRadiusPerHeight = t * (sqrt(1.0 + t * t) - t);
      precise float footprint = h * t;  // the cone's radius at the hit
      precise vec2 direction = toHit / h;
      precise float adj = h;
      precise float coverage = 0.0;
      precise vec3 sum = vec3(0.0);
      for (int i = 0; i < maxSamples && coverage < 1.0; ++i) {
        precise float r = adj * inRadiusPerHeight;
        precise float ratio = r / footprint;
        precise float share = min(ratio * ratio, 1.0 - coverage);
        precise vec2 centre = origin + direction * (adj - r);
        sum += SampleCircle(centre, max(2.0 * r, 1.0)) * share;
        coverage += share;
        adj -= 2.0 * r;
      }
      radiance = sum / coverage;
    }
  }
  reflected[index] = radiance.r;
  reflected[index + plane] = radiance.g;
  reflected[index + 2 * plane] = radiance.b;
}
