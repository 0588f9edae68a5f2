// Sky light (docs/pipeline.md §Sky light): diffuse = albedo (1 - metallic) E(n) / pi V(p, n), with E
// the environment's irradiance (a constant environment: its radiance; else nine SH coefficients) and
// V read from the sky visibility volume, plus albedo (1 - metallic) max(E_w(p, n) / pi, 0) from the
// interreflection volume on the same grid where there is one, and that volume read towards the
// mirror direction (`reflected`, for the composite); lit = direct + diffuse. A background pixel's lit value is
// the environment seen along its ray.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Word0 { uint word0[]; };
layout(std430, binding = 1) readonly buffer Word1 { uint word1[]; };
layout(std430, binding = 2) readonly buffer Word2 { float depth[]; };
layout(std430, binding = 3) readonly buffer Direct { float direct[]; };          // three planes
layout(std430, binding = 4) readonly buffer Volume { float coefficients[]; };    // 4 per cell
layout(std430, binding = 5) writeonly buffer Diffuse { float diffuse[]; };       // three planes
layout(std430, binding = 6) writeonly buffer Visibility { float visibility[]; };
layout(std430, binding = 7) writeonly buffer Lit { float lit[]; };               // three planes
// The interreflection volume's R, G and B coefficients (4 per cell each), one after the other.
layout(std430, binding = 8) readonly buffer Interreflection { float interreflection[]; };
layout(std430, binding = 9) writeonly buffer Reflected { float reflected[]; };  // three planes

uniform ivec3 cells;
uniform vec3 origin;
uniform float cellSize;
uniform float inverseCellSize;
uniform int constantEnvironment;  // 1: every irradiance read is `environmentRadiance`; else the
                                  // tables: the SH below, the octahedral levels (common.glsl)
uniform vec3 environmentRadiance;
uniform vec3 irradianceSh[9];
uniform int hasInterreflection;  // 1: the interreflection volume is bound

float Lerp(float a, float b, float w) {
  precise float v = a * (1.0 - w) + b * w;
  return v;
}

// SampleVolume: the cells around p + n cellSize / 2 and the trilinear weights.
struct VolumeSample {
  ivec3 i0, i1;
  vec3 f;
};

VolumeSample SampleVolume(vec3 p, vec3 n) {
  precise float offset = 0.5 * cellSize;
  precise vec3 q = (p + n * offset - origin) * inverseCellSize - 0.5;
  VolumeSample s;
  precise vec3 f;
  for (int a = 0; a < 3; ++a) {
    precise float c = clamp(q[a], 0.0, float(cells[a] - 1));
    s.i0[a] = int(c);
    s.i1[a] = min(s.i0[a] + 1, cells[a] - 1);
    f[a] = c - float(s.i0[a]);
  }
  s.f = f;
  return s;
}

// ReadVolumeToward of table `table` (0: the visibility; 1, 2, 3: the interreflection's R, G, B): x,
// then y, then z, then k0 + kx n.x + ky n.y + kz n.z towards a unit direction n, unclamped.
float Coefficient(int table, ivec3 c, int k) {
  const int index = ((c.z * cells.y + c.y) * cells.x + c.x) * 4 + k;
  return table == 0 ? coefficients[index] : interreflection[(table - 1) * cells.x * cells.y * cells.z * 4 + index];
}

float ReadVolume(int table, VolumeSample s, vec3 n) {
  const ivec3 i0 = s.i0, i1 = s.i1;
  const vec3 f = s.f;
  precise float v[4];
  for (int k = 0; k < 4; ++k) {
    const float x00 = Lerp(Coefficient(table, ivec3(i0.x, i0.y, i0.z), k), Coefficient(table, ivec3(i1.x, i0.y, i0.z), k), f.x);
    const float x10 = Lerp(Coefficient(table, ivec3(i0.x, i1.y, i0.z), k), Coefficient(table, ivec3(i1.x, i1.y, i0.z), k), f.x);
    const float x01 = Lerp(Coefficient(table, ivec3(i0.x, i0.y, i1.z), k), Coefficient(table, ivec3(i1.x, i0.y, i1.z), k), f.x);
    const float x11 = Lerp(Coefficient(table, ivec3(i0.x, i1.y, i1.z), k), Coefficient(table, ivec3(i1.x, i1.y, i1.z), k), f.x);
    v[k] = Lerp(Lerp(x00, x10, f.y), Lerp(x01, x11, f.y), f.z);
  }
  precise float sum = v[0] + v[1] * n.x;
  sum = sum + v[2] * n.y;
  sum = sum + v[3] * n.z;
  return sum;
}

// E(n) / pi from the SH coefficients, summed in basis order; clamped to >= 0.
vec3 Irradiance(vec3 n) {
  if (constantEnvironment != 0) return environmentRadiance;
  precise float y[9];
  y[0] = 0.282095;
  y[1] = 0.488603 * n.y;
  y[2] = 0.488603 * n.z;
  y[3] = 0.488603 * n.x;
  y[4] = 1.092548 * n.x * n.y;
  y[5] = 1.092548 * n.y * n.z;
  y[6] = 0.315392 * (3.0 * n.z * n.z - 1.0);
  y[7] = 1.092548 * n.x * n.z;
  y[8] = 0.546274 * (n.x * n.x - n.y * n.y);
  precise vec3 sum = irradianceSh[0] * y[0];
  for (int k = 1; k < 9; ++k) sum = sum + irradianceSh[k] * y[k];
  return max(sum, vec3(0.0));
}

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;
  const int index = pixel.y * imageSize.x + pixel.x;
  const int plane = imageSize.x * imageSize.y;
  const float d = depth[index];
  precise vec3 light = vec3(0.0);
  precise vec3 surroundings = vec3(0.0);
  float v = 1.0;
  if (d == kBackgroundDepth) {
    // The environment itself, seen along the pixel's ray (a constant one is already in `direct`).
    if (constantEnvironment == 0) {
      light = EnvironmentRadiance(Rotate(Normalize3(PixelRayDirection(vec2(pixel) + 0.5))));
    }
  } else {
    const vec3 normal = Rotate(UnpackNormal(word1[index]));
    const vec3 ray = PixelRayDirection(vec2(pixel) + 0.5);
    precise vec3 viewPosition = vec3(ray.x * d, ray.y * d, -d);
    precise vec3 position = Rotate(viewPosition) + viewToWorld[3];
    const VolumeSample s = SampleVolume(position, normal);
    v = clamp(ReadVolume(0, s, normal), 0.0, 1.0);
    const uint w0 = word0[index];
    precise vec3 albedo = UnpackAlbedo(w0) * (1.0 - UnpackMetallic(w0));
    light = albedo * Irradiance(normal) * v;
    if (hasInterreflection != 0) {
      precise vec3 interreflected;
      for (int c = 0; c < 3; ++c) interreflected[c] = max(ReadVolume(1 + c, s, normal), 0.0);
      light = light + albedo * interreflected;
      // The mirror direction as the composite takes it: r = n (2 n.v) - v in view space, into the world.
      const vec3 viewNormal = UnpackNormal(word1[index]);
      const vec3 toViewer = Normalize3(-ray);
      precise vec3 reflection = viewNormal * (2.0 * Dot3(viewNormal, toViewer)) - toViewer;
      const vec3 mirror = Rotate(reflection);
      for (int c = 0; c < 3; ++c) surroundings[c] = max(ReadVolume(1 + c, s, mirror), 0.0);
    }
  }
  const bool environmentSeen = d == kBackgroundDepth && constantEnvironment == 0;
  for (int c = 0; c < 3; ++c) {
    diffuse[index + c * plane] = environmentSeen ? 0.0 : light[c];
    precise float sum = direct[index + c * plane] + light[c];
    lit[index + c * plane] = environmentSeen ? light[c] : sum;
    if (hasInterreflection != 0) reflected[index + c * plane] = surroundings[c];
  }
  visibility[index] = v;
}
