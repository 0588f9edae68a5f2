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
