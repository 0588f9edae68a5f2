// The rasterizer's set-up and depth key (docs/pipeline.md §Rasterizer, steps 1-5): each triangle
// transformed, clipped in float64, snapped to 8 sub-pixel bits and set up as the oracle sets it up,
// so that a fragment GL's own rasterizer produces gets the oracle's depth key at its pixel. GL
// decides the coverage; the key written through gl_FragDepth makes the depth test the oracle's.
// Integer arithmetic is done in float64, exact below 2^53 (the spec allows either): inside the
// guard band the snapped coordinates are below 2^24.
// Included after common.glsl and surface.glsl.

const int kSubPixelScale = 256;
const int kHalfPixel = 128;
const int kRasterTileSize = 64;
const double kGuardBandPixels = 16384.0LF;
// Clipped by six planes a triangle has at most 9 vertices, so its fan at most 7 triangles.
const int kMaxPieces = 7;

// ScreenTriangle (core/raster/raster_tile.h): the snapped vertices ordered for positive area
// (x.w, y.w unused) and the depth key's plane: key at the centre of pixel (px, py) = key.x +
// key.y px + key.z py (key.w unused).
struct ScreenTriangle {
  ivec4 x;
  ivec4 y;
  dvec4 key;
};
// kMaxPieces per triangle; pieceCount[t] of them are set up (0: culled or outside the view).
layout(std430, binding = 3) buffer ScreenTriangles { ScreenTriangle pieces[]; };
layout(std430, binding = 4) buffer PieceCounts { uint pieceCount[]; };
// Per triangle: not 0 where the pass culls its back face as one of a closed surface's (§Shadow map:
// closed surfaces wholly beyond the light's near plane, without cut-outs); all 0 for the camera.
layout(std430, binding = 16) readonly buffer ClosedCulled { uint closedCulled[]; };

// The target the triangles are set up for: the image or the shadow map, and its view-projection.
uniform ivec2 rasterSize;
uniform mat4 viewProjection;
// Below 8, the vertex shaders snap their window positions to steps of 2^-snapBits pixel before GL
// snaps them to its own grid: a coarser rasterizer, emulated, to measure what it changes.
uniform int snapBits;

// A clip position with its window position on the grid of snapBits bits (vertices in front of the
// eye; GL clips the others).
vec4 SnapToGrid(vec4 clip) {
  if (snapBits >= 8 || !(clip.w > 0.0)) return clip;
  const float steps = float(1 << snapBits);
  precise vec2 window = (clip.xy / clip.w * 0.5 + 0.5) * vec2(rasterSize);
  precise vec2 snapped = round(window * steps) / steps;
  precise vec2 ndc = snapped / vec2(rasterSize) * 2.0 - 1.0;
  return vec4(ndc * clip.w, clip.zw);
}

// Whether the centre of `pixel` is inside `t`: its exact edge functions with the top-left rule.
bool Covers(ScreenTriangle t, ivec2 pixel) {
  const double sx = double(pixel.x * kSubPixelScale + kHalfPixel), sy = double(pixel.y * kSubPixelScale + kHalfPixel);
  for (int e = 0; e < 3; ++e) {
    const int from = (e + 1) % 3, to = (e + 2) % 3;
    const int dx = t.x[to] - t.x[from], dy = t.y[to] - t.y[from];
    const bool topLeft = dy < 0 || (dy == 0 && dx > 0);
    precise double c = double(dy) * double(t.x[from]) - double(dx) * double(t.y[from]) - (topLeft ? 0.0LF : 1.0LF);
    precise double edge = double(-dy) * sx + double(dx) * sy + c;
    if (edge < 0.0LF) return false;
  }
  return true;
}

// The depth key at `pixel` (step 5): the plane relative to the pixel's 64x64 tile, in float32.
float KeyAt(ScreenTriangle t, ivec2 pixel) {
  const ivec2 tile = (pixel / kRasterTileSize) * kRasterTileSize;
  precise double base = t.key.x + t.key.y * double(tile.x) + t.key.z * double(tile.y);
  const float keyBase = float(base), keyDx = float(t.key.y), keyDy = float(t.key.z);
  precise float key = keyBase + keyDx * float(pixel.x - tile.x) + keyDy * float(pixel.y - tile.y);
  return key;
}

// The oracle's depth key of `triangle` at `pixel`: of the piece of its clipped fan that covers the
// pixel, or, where GL covers a pixel the oracle does not, of its first piece (the same plane up to
// rounding). False where the oracle set up no piece (culled, zero area after its snapping).
bool OracleKey(uint triangle, ivec2 pixel, out float key) {
  key = 0.0;
  const uint count = pieceCount[triangle];
  if (count == 0u) return false;
  const uint first = triangle * uint(kMaxPieces);
  uint chosen = first;
  for (uint i = 0u; i < count; ++i) {
    if (Covers(pieces[first + i], pixel)) {
      chosen = first + i;
      break;
    }
  }
  key = KeyAt(pieces[chosen], pixel);
  return true;
}
