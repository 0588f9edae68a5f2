// What several passes of the port share, written from docs/pipeline.md (§Conventions, §G-buffer,
// §Hi-Z pyramid). The runner puts this file between the `#version` line and each pass's source.
//
// The oracle is built with -ffp-contract=off: every product is rounded before it is added. GLSL
// lets a compiler fuse a * b + c into one fma (Mesa does on llvmpipe), so every float variable of
// the port is `precise`, which forbids fusing and reordering the operations it is computed from.

// The pixel-centre view ray's direction, (x, y, -1) (§Conventions), for image position `position`.
// `imageSize` and `tanHalf` (tanHalfX, tanHalfY) come from the runner's MakePerspective.
uniform ivec2 imageSize;
uniform vec2 tanHalf;

vec3 PixelRayDirection(vec2 position) {
  precise float x = (2.0 * position.x / float(imageSize.x) - 1.0) * tanHalf.x;
  precise float y = (1.0 - 2.0 * position.y / float(imageSize.y)) * tanHalf.y;
  return vec3(x, y, -1.0);
}

// viewToWorld's columns 0-3 (the rotation's three, then the translation), xyz each: the passes
// that work in world space (the sky light, the composite's environment) set it.
uniform vec3 viewToWorld[4];

// m0 a + m1 b + m2 c, each row's products rounded and added left to right (glm's mat3 * vec3).
vec3 Rotate(vec3 v) {
  precise vec3 r = viewToWorld[0] * v.x + viewToWorld[1] * v.y;
  precise vec3 s = r + viewToWorld[2] * v.z;
  return s;
}

// glm's dot: (a.x b.x + a.y b.y) + a.z b.z, each product rounded (§Direct light).
float Dot3(vec3 a, vec3 b) {
  precise float xy = a.x * b.x + a.y * b.y;
  precise float xyz = xy + a.z * b.z;
  return xyz;
}

// glm's normalize: a * (1 / |a|).
vec3 Normalize3(vec3 a) {
  precise float inverseLength = 1.0 / sqrt(Dot3(a, a));
  precise vec3 unit = a * inverseLength;
  return unit;
}

// Every radiance buffer holds finite values in [0, 65504], the largest half float (§Conventions):
// NaN and negatives (-inf too) -> 0, above the cap (+inf too) -> the cap.
const float kMaxRadiance = 65504.0;
float SanitizeRadiance(float v) { return v > 0.0 ? min(v, kMaxRadiance) : 0.0; }

// G-buffer word 2 of a background pixel: +inf.
const float kBackgroundDepth = uintBitsToFloat(0x7F800000u);

// The G-buffer's normal encoding (§G-buffer, "Normal encodings"): kNormalXyz8, else oct24 (1).
const int kNormalXyz8 = 0;
uniform int normalEncoding;

float DequantizeSigned(uint code, float maxCode) {
  precise float t = float(code) / maxCode * 2.0 - 1.0;
  return t;
}

vec3 UnpackNormal(uint word1) {
  precise vec3 n;
  if (normalEncoding == kNormalXyz8) {
    n = vec3(DequantizeSigned(word1 & 0xFFu, 255.0), DequantizeSigned((word1 >> 8) & 0xFFu, 255.0),
             DequantizeSigned((word1 >> 16) & 0xFFu, 255.0));
  } else {
    n.x = DequantizeSigned(word1 & 0xFFFu, 4095.0);
    n.y = DequantizeSigned((word1 >> 12) & 0xFFFu, 4095.0);
    n.z = 1.0 - abs(n.x) - abs(n.y);
    precise float k = max(-n.z, 0.0);
    n.x += n.x >= 0.0 ? -k : k;
    n.y += n.y >= 0.0 ? -k : k;
  }
  // Three divisions by the length (not a multiplication by its reciprocal, as Normalize3).
  precise vec3 unit = n / sqrt(Dot3(n, n));
  return unit;
}

// Perceptual roughness and metallic: code / 255.
float UnpackRoughness(uint word1) {
  precise float r = float(word1 >> 24) / 255.0;
  return r;
}
float UnpackMetallic(uint word0) {
  precise float m = float(word0 >> 24) / 255.0;
  return m;
}

// The linear value of each 8-bit sRGB code (core/color.h's table, uploaded by the runner): the
// albedo of G-buffer word 0. Binding 15 in every pass that decodes albedo.
layout(std430, binding = 15) readonly buffer SrgbDecode { float srgbToLinear[]; };

vec3 UnpackAlbedo(uint word0) {
  return vec3(srgbToLinear[word0 & 0xFFu], srgbToLinear[(word0 >> 8) & 0xFFu], srgbToLinear[(word0 >> 16) & 0xFFu]);
}

// F0 = mix(0.04, albedo, metallic) evaluated as glm's mix, x (1 - a) + y a (GLSL's mix may
// compile to another form).
vec3 SpecularF0(vec3 albedo, float metallic) {
  precise vec3 f0 = vec3(0.04) * (1.0 - metallic) + albedo * metallic;
  return f0;
}

// The last source texel (inclusive) of destination texel `x`'s footprint along one axis, whose
// first is 2x: the last destination texel reaches the source's end (§Hi-Z pyramid, footprint).
int FootprintEnd(int x, int destinationSize, int sourceSize) {
  return x + 1 == destinationSize ? sourceSize - 1 : 2 * x + 1;
}

// The environment's octahedral levels (§Environment lighting), core's tables uploaded by the
// runner where the environment is not a constant: level k is `levelSize[k] + 2` texels on a side
// (a one-texel border across the seams), three planes, from float `levelOffset[k]`, rows in order.
layout(std430, binding = 14) readonly buffer EnvironmentLevels { float environmentTexels[]; };
const int kEnvironmentLevels = 6;
uniform int levelSize[kEnvironmentLevels];
uniform int levelOffset[kEnvironmentLevels];

float SignNotZero(float t) { return t >= 0.0 ? 1.0 : -1.0; }

// OctahedralEncode: folded about world y, the sky the inner diamond.
vec2 OctahedralEncode(vec3 d) {
  precise float l1 = abs(d.x) + abs(d.y);
  l1 = l1 + abs(d.z);
  precise float x = d.x / l1;
  precise float z = d.z / l1;
  if (d.y < 0.0) {
    precise float fx = (1.0 - abs(z)) * SignNotZero(x);
    precise float fz = (1.0 - abs(x)) * SignNotZero(z);
    x = fx;
    z = fz;
  }
  precise vec2 uv = vec2(x, z) * 0.5 + 0.5;
  return uv;
}

vec3 EnvironmentTexel(int level, int i, int j) {
  const int side = levelSize[level] + 2;
  const int at = levelOffset[level] + j * side + i;
  const int plane = side * side;
  return vec3(environmentTexels[at], environmentTexels[at + plane], environmentTexels[at + 2 * plane]);
}

// SampleLevel (core): bilinear in the bordered level, texel i's centre at bordered coordinate i + 1.5.
vec3 SampleEnvironmentLevel(int level, vec2 uv) {
  const float n = float(levelSize[level]);
  precise float x = uv.x * n + 0.5;
  precise float y = uv.y * n + 0.5;
  const int i = min(int(x), levelSize[level]);
  const int j = min(int(y), levelSize[level]);
  precise float fx = x - float(i);
  precise float fy = y - float(j);
  precise vec3 top = EnvironmentTexel(level, i, j) * (1.0 - fx) + EnvironmentTexel(level, i + 1, j) * fx;
  precise vec3 bottom = EnvironmentTexel(level, i, j + 1) * (1.0 - fx) + EnvironmentTexel(level, i + 1, j + 1) * fx;
  precise vec3 bilinear = top * (1.0 - fy) + bottom * fy;
  return bilinear;
}

// EnvironmentRadiance: level 0 towards the world-space unit `direction`.
vec3 EnvironmentRadiance(vec3 direction) { return SampleEnvironmentLevel(0, OctahedralEncode(direction)); }

// PrefilteredEnvironment: the two levels around roughness * 5, mixed linearly.
vec3 PrefilteredEnvironment(vec3 direction, float roughness) {
  precise float position = clamp(roughness, 0.0, 1.0) * float(kEnvironmentLevels - 1);
  const int lower = min(int(position), kEnvironmentLevels - 2);
  precise float f = position - float(lower);
  const vec2 uv = OctahedralEncode(direction);
  precise vec3 mixed = SampleEnvironmentLevel(lower, uv) * (1.0 - f) + SampleEnvironmentLevel(lower + 1, uv) * f;
  return mixed;
}
