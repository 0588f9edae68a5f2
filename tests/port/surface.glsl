// The scene's mesh, materials and textures, and the surface point of a pixel on a triangle
// (docs/pipeline.md §G-buffer "Resolve", steps 1, 3 and 4; core/surface.h): what the G-buffer resolve
// and the rasterizer's alpha test share, for the camera or a light's view. Included after
// common.glsl by the passes that read the mesh.

// The mesh as the runner uploads it (core/mesh.h): xyz per vertex, uv per vertex, three indices and
// a material per triangle.
layout(std430, binding = 5) readonly buffer MeshPositions { float positions[]; };
layout(std430, binding = 6) readonly buffer MeshUvs { vec2 uvs[]; };
layout(std430, binding = 7) readonly buffer MeshIndices { uint indices[]; };
layout(std430, binding = 8) readonly buffer MeshMaterials { uint triangleMaterial[]; };

// core/material.h: baseColor.rgb and metallic; roughness, alpha cut-off, two-sided (0 or 1);
// the texture indices (-1: none) of the base colour, metallic, roughness and alpha maps.
struct Material {
  vec4 baseColorMetallic;
  vec4 roughnessCutoffTwoSided;
  ivec4 textures;
};
layout(std430, binding = 9) readonly buffer Materials { Material materials[]; };

// core/texture.h: `info` is (levels, encoding (0 sRGB, 1 linear), source channels, max(width,
// height) of level 0); level k is (width, height, offset of its first texel in `texels`).
const int kMaxTextureLevels = 16;
struct TextureInfo {
  ivec4 info;
  ivec4 level[kMaxTextureLevels];
};
layout(std430, binding = 12) readonly buffer Textures { TextureInfo textures[]; };
// RGBA8 texels, R in the low byte, every level of every texture.
layout(std430, binding = 13) readonly buffer Texels { uint texels[]; };

// The view the surface is seen from: world -> view (glm's matrix), and whether it is orthographic
// (a directional light's map); common.glsl's imageSize and tanHalf are its size and half extents.
uniform mat4 surfaceView;
uniform int orthographicView;

vec3 MeshPosition(uint vertex) {
  return vec3(positions[3u * vertex], positions[3u * vertex + 1u], positions[3u * vertex + 2u]);
}

// glm's mat4 * vec4 with w = 1: (m0 x + m1 y) + (m2 z + m3), each product rounded.
vec4 Transform(mat4 m, vec3 p) {
  precise vec4 xy = m[0] * p.x + m[1] * p.y;
  precise vec4 zw = m[2] * p.z + m[3];
  precise vec4 sum = xy + zw;
  return sum;
}

vec3 ViewPosition(uint vertex) { return Transform(surfaceView, MeshPosition(vertex)).xyz; }

// glm's cross.
vec3 Cross3(vec3 a, vec3 b) {
  precise vec3 c = vec3(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
  return c;
}

// The view ray through image position `position` (PixelRay): from the eye along (x, y, -1), or,
// orthographic, from (x, y, 0) along -z.
void ViewRay(vec2 position, out vec3 origin, out vec3 direction) {
  const vec3 d = PixelRayDirection(position);
  origin = orthographicView != 0 ? vec3(d.xy, 0.0) : vec3(0.0);
  direction = orthographicView != 0 ? vec3(0.0, 0.0, -1.0) : d;
}

bool IsFinite(float x) { return !isnan(x) && !isinf(x); }

// Barycentrics (b1, b2) where the ray meets the plane of (p0, p0 + e1, p0 + e2) (Moller-Trumbore
// without the bounds test), written to `b` unless the ray is parallel; true when written and finite
// (core/surface.cpp leaves a non-finite result in `b`, and so does this).
bool RayPlaneBarycentrics(vec3 origin, vec3 direction, vec3 p0, vec3 e1, vec3 e2, inout vec2 b) {
  const vec3 p = Cross3(direction, e2);
  const float det = Dot3(e1, p);
  if (!(abs(det) > 1e-30)) return false;
  precise float invDet = 1.0 / det;
  precise vec3 s = origin - p0;
  const vec3 q = Cross3(s, e1);
  precise vec2 result = vec2(Dot3(s, p) * invDet, Dot3(direction, q) * invDet);
  b = result;
  return IsFinite(b.x) && IsFinite(b.y);
}

// glm's clamp to [0, 1]: max(a, b) = a < b ? b : a, then min(a, b) = b < a ? b : a.
float GlmClamp01(float x) {
  const float low = x < 0.0 ? 0.0 : x;
  return 1.0 < low ? 1.0 : low;
}

// SurfacePoint (core/surface.h) of `triangle` under the centre of `pixel`.
struct SurfacePoint {
  vec3 weights;
  vec2 uv;
  float uvFootprint;
  vec2 baryStepX, baryStepY;  // to the rays one pixel right and down (unclamped); 0 where one misses
};

float Length2(vec2 v) {
  precise float d = v.x * v.x + v.y * v.y;
  return sqrt(d);
}

SurfacePoint SurfaceAt(uint triangle, ivec2 pixel, bool withSteps) {
  const uint i0 = indices[3u * triangle], i1 = indices[3u * triangle + 1u], i2 = indices[3u * triangle + 2u];
  const vec3 p0 = ViewPosition(i0);
  precise vec3 e1 = ViewPosition(i1) - p0;
  precise vec3 e2 = ViewPosition(i2) - p0;
  const vec2 c = vec2(pixel) + 0.5;
  vec3 origin, direction;
  ViewRay(c, origin, direction);
  vec2 centre = vec2(1.0 / 3.0);
  const bool hit = RayPlaneBarycentrics(origin, direction, p0, e1, e2, centre);
  // Clamped: the centre is inside the snapped triangle, so b leaves [0, 1] only by rounding.
  precise vec2 b = vec2(GlmClamp01(centre.x), GlmClamp01(centre.y));
  precise float sum = b.x + b.y;
  if (sum > 1.0) b = vec2(b.x / sum, b.y / sum);
  SurfacePoint s;
  precise float w0 = 1.0 - b.x - b.y;
  s.weights = vec3(w0, b.x, b.y);
  const vec2 uv0 = uvs[i0];
  precise vec2 du1 = uvs[i1] - uv0;
  precise vec2 du2 = uvs[i2] - uv0;
  precise vec2 uv = uv0 + du1 * b.x + du2 * b.y;
  s.uv = uv;
  s.uvFootprint = 0.0;
  s.baryStepX = vec2(0.0);
  s.baryStepY = vec2(0.0);
  vec2 bx = vec2(0.0), by = vec2(0.0);
  vec3 ox, dx, oy, dy;
  ViewRay(c + vec2(1.0, 0.0), ox, dx);
  ViewRay(c + vec2(0.0, 1.0), oy, dy);
  // Unclamped: the steps are derivatives of the plane's parameterisation.
  if (withSteps && hit && RayPlaneBarycentrics(ox, dx, p0, e1, e2, bx) &&
      RayPlaneBarycentrics(oy, dy, p0, e1, e2, by)) {
    precise vec2 stepX = bx - centre;
    precise vec2 stepY = by - centre;
    s.baryStepX = stepX;
    s.baryStepY = stepY;
    precise vec2 ddx = du1 * stepX.x + du2 * stepX.y;
    precise vec2 ddy = du1 * stepY.x + du2 * stepY.y;
    const float footprint = max(Length2(ddx), Length2(ddy));
    s.uvFootprint = IsFinite(footprint) ? footprint : 0.0;
  }
  return s;
}

// core/texture.cpp's Log2 for x > 1: exponent and mantissa from the bits, the atanh series of ln.
float Log2Series(float x) {
  const uint bits = floatBitsToUint(x);
  const int exponent = int((bits >> 23) & 0xFFu) - 126;
  const float mantissa = uintBitsToFloat((bits & 0x7FFFFFu) | 0x3F800000u);
  precise float s = (mantissa - 1.0) / (mantissa + 1.0);
  precise float s2 = s * s;
  precise float series =
      1.0 + s2 * (1.0 / 3.0 + s2 * (1.0 / 5.0 + s2 * (1.0 / 7.0 + s2 * (1.0 / 9.0 + s2 * (1.0 / 11.0)))));
  precise float log2x = float(exponent - 1) + 2.0 * s * series * 1.44269504;
  return log2x;
}

// The fraction of a texture coordinate; non-finite coordinates read as 0.
float Repeat(float x) {
  precise float f = x - floor(x);
  return IsFinite(x) ? f : 0.0;
}

int WrapIndex(int i, int size) { return i < 0 ? i + size : (i >= size ? i - size : i); }

vec4 Texel(int texture, ivec4 level, int x, int y) {
  const uint word = texels[level.z + y * level.x + x];
  const uvec4 code = uvec4(word & 0xFFu, (word >> 8) & 0xFFu, (word >> 16) & 0xFFu, word >> 24);
  precise vec4 unorm = vec4(code) / 255.0;
  if (textures[texture].info.y == 0) unorm.rgb = vec3(srgbToLinear[code.r], srgbToLinear[code.g], srgbToLinear[code.b]);
  return unorm;
}

// Bilinear in one level, texel centres at (i + 0.5) / size, v = 0 at the bottom row, repeat.
vec4 SampleBilinear(int texture, ivec4 level, float u, float v) {
  precise float x = u * float(level.x) - 0.5;
  precise float y = (1.0 - v) * float(level.y) - 0.5;
  const float x0 = floor(x), y0 = floor(y);
  precise float fx = x - x0;
  precise float fy = y - y0;
  const int ix0 = WrapIndex(int(x0), level.x), ix1 = WrapIndex(int(x0) + 1, level.x);
  const int iy0 = WrapIndex(int(y0), level.y), iy1 = WrapIndex(int(y0) + 1, level.y);
  precise vec4 top = Texel(texture, level, ix0, iy0) * (1.0 - fx) + Texel(texture, level, ix1, iy0) * fx;
  precise vec4 bottom = Texel(texture, level, ix0, iy1) * (1.0 - fx) + Texel(texture, level, ix1, iy1) * fx;
  precise vec4 bilinear = top * (1.0 - fy) + bottom * fy;
  return bilinear;
}

// SampleTexture: trilinear, level log2(footprint * max(width, height)) clamped to the chain.
vec4 SampleTexture(int texture, vec2 uv, float footprint) {
  const ivec4 info = textures[texture].info;
  const int lastLevel = info.x - 1;
  precise float scaled = footprint * float(info.w);
  float lambda = 0.0;
  if (scaled >= float(1 << lastLevel)) {
    lambda = float(lastLevel);
  } else if (scaled > 1.0) {
    lambda = Log2Series(scaled);
  }
  const float u = Repeat(uv.x), v = Repeat(uv.y);
  const int level = int(lambda);
  precise float blend = lambda - float(level);
  const vec4 fine = SampleBilinear(texture, textures[texture].level[level], u, v);
  if (blend == 0.0) return fine;
  const vec4 coarse = SampleBilinear(texture, textures[texture].level[level + 1], u, v);
  precise vec4 mixed = fine * (1.0 - blend) + coarse * blend;
  return mixed;
}

// The rasterizer's alpha test (docs/pipeline.md §Rasterizer step 7): the alpha texture's mask (its
// alpha channel for grey+alpha and RGBA files, else its first) at the pixel's surface point, against
// the material's cut-off.
bool PassesAlphaTest(uint triangle, ivec2 pixel) {
  const Material material = materials[triangleMaterial[triangle]];
  const int texture = material.textures.w;
  if (texture < 0) return true;
  const SurfacePoint s = SurfaceAt(triangle, pixel, true);
  const vec4 texel = SampleTexture(texture, s.uv, s.uvFootprint);
  const int channels = textures[texture].info.z;
  const float alpha = channels == 2 || channels == 4 ? texel.w : texel.x;
  return alpha >= material.roughnessCutoffTwoSided.y;
}
