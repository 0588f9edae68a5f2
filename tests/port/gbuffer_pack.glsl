// G-buffer words 0 and 1 (docs/pipeline.md §G-buffer): the codes, and a material's constants
// times its textures' samples, as passes/gbuffer.cpp's ResolveMaterial makes them. Shared by the
// resolve and the conventional G-buffer pass. Included after common.glsl and surface.glsl.

layout(std430, binding = 10) readonly buffer MeshNormals { float normals[]; };
// The 255 linear values halfway between sRGB codes in encoded space (core/color.h,
// SrgbEncodeThresholds): code k rounds up to k + 1 from thresholds[k] on.
layout(std430, binding = 11) readonly buffer SrgbThresholds { float srgbThresholds[]; };

// LinearToSrgbCode: the number of thresholds at or below x (0 for NaN and x <= 0).
uint LinearToSrgbCode(float x) {
  if (!(x > 0.0)) return 0u;
  uint low = 0u, high = 255u;  // the count lies in [low, high]
  while (low < high) {
    const uint middle = (low + high + 1u) / 2u;
    if (srgbThresholds[middle - 1u] <= x) {
      low = middle;
    } else {
      high = middle - 1u;
    }
  }
  return low;
}

uint UnormCode8(float value) {
  if (!(value > 0.0)) return 0u;
  if (value >= 1.0) return 255u;
  precise float scaled = value * 255.0 + 0.5;
  return uint(scaled);
}

uint QuantizeSigned(float value, float maxCode) {
  const float clamped = !(value > -1.0) ? -1.0 : (value > 1.0 ? 1.0 : value);
  precise float scaled = (clamped * 0.5 + 0.5) * maxCode + 0.5;
  return uint(scaled);
}

uint EncodeNormal(vec3 n) {
  if (normalEncoding == kNormalXyz8)
    return QuantizeSigned(n.x, 255.0) | QuantizeSigned(n.y, 255.0) << 8 | QuantizeSigned(n.z, 255.0) << 16;
  precise float l1 = abs(n.x) + abs(n.y) + abs(n.z);
  precise float u = n.x / l1;
  precise float v = n.y / l1;
  if (n.z < 0.0) {
    precise float foldedU = (1.0 - abs(v)) * SignNotZero(u);
    precise float foldedV = (1.0 - abs(u)) * SignNotZero(v);
    u = foldedU;
    v = foldedV;
  }
  return QuantizeSigned(u, 4095.0) | QuantizeSigned(v, 4095.0) << 12;
}

uint PackAlbedoMetallic(vec3 albedo, float metallic) {
  return LinearToSrgbCode(albedo.x) | LinearToSrgbCode(albedo.y) << 8 | LinearToSrgbCode(albedo.z) << 16 |
         UnormCode8(metallic) << 24;
}

vec3 MeshNormal(uint vertex) {
  return vec3(normals[3u * vertex], normals[3u * vertex + 1u], normals[3u * vertex + 2u]);
}

// §G-buffer "Specular anti-aliasing": the most the normal's variance adds to GGX alpha^2 (0: off).
uniform float specularAaKappa;

// NormalVariance: the steps of the interpolated normal `m` across it, over |m|, as alpha^2.
float NormalVariance(vec3 m, vec3 stepX, vec3 stepY) {
  const float lengthSquared = Dot3(m, m);
  precise vec3 acrossX = stepX - m * (Dot3(m, stepX) / lengthSquared);
  precise vec3 acrossY = stepY - m * (Dot3(m, stepY) / lengthSquared);
  precise float variance = (Dot3(acrossX, acrossX) + Dot3(acrossY, acrossY)) / lengthSquared * 0.31830988;
  return variance;
}

// WidenedRoughness: alpha^2 + min(variance, kappa), at most 1, back by two square roots; the
// roughness itself where nothing is added (std::min(a, b) = b < a ? b : a).
float WidenedRoughness(float roughness, float variance) {
  const float added = specularAaKappa < variance ? specularAaKappa : variance;
  if (!(added > 0.0)) return roughness;
  precise float alpha = roughness * roughness;
  precise float widened = alpha * alpha + added;
  return sqrt(sqrt(1.0 < widened ? 1.0 : widened));
}

// Words 0 and 1 of a pixel of `material` with the unit view-space `normal`, its textures sampled at
// `uv` with the UV `footprint` (unused by an untextured material), the roughness widened by the
// normal's `variance` over the pixel.
uvec2 MaterialWords(Material material, vec3 normal, vec2 uv, float footprint, float variance) {
  const ivec4 maps = material.textures;  // base colour, metallic, roughness, alpha
  uint word0;
  if (maps.x < 0 && maps.y < 0) {
    word0 = PackAlbedoMetallic(material.baseColorMetallic.rgb, material.baseColorMetallic.w);
  } else {
    precise vec3 albedo = material.baseColorMetallic.rgb;
    precise float metallic = material.baseColorMetallic.w;
    if (maps.x >= 0) albedo = albedo * SampleTexture(maps.x, uv, footprint).rgb;
    if (maps.y >= 0) metallic = metallic * SampleTexture(maps.y, uv, footprint).x;
    word0 = PackAlbedoMetallic(albedo, metallic);
  }
  precise float roughness = material.roughnessCutoffTwoSided.x;
  if (maps.z >= 0) roughness = roughness * SampleTexture(maps.z, uv, footprint).x;
  return uvec2(word0, EncodeNormal(normal) | UnormCode8(WidenedRoughness(roughness, variance)) << 24);
}
