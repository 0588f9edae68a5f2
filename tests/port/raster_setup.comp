// §Rasterizer steps 1-4 for every triangle (raster.glsl): transform, clip against near, far and
// the guard band in float64, snap, and set up each piece of the clipped fan as the oracle does, into
// `pieces` and `pieceCount`. Triangle t is invocation (x + rowLength y).
layout(local_size_x = 8, local_size_y = 8) in;

uniform int triangleCount;
uniform int rowLength;
uniform int cullBackFaces;  // the camera's G-buffer culls (unless two-sided); shadow maps draw both faces but closedCulled's

const int kPlanes = 6;

double RoundHalfAwayToInt(double x) {
  const int truncated = int(x);
  precise double fraction = x - double(truncated);
  return double(truncated + int(fraction >= 0.5LF) - int(fraction <= -0.5LF));
}

// The clip-space distance to plane `plane`: near w - z, far z, the guard band's four.
double ClipDistance(dvec4 v, int plane) {
  precise double guardX = 1.0LF + 2.0LF * kGuardBandPixels / double(rasterSize.x);
  precise double guardY = 1.0LF + 2.0LF * kGuardBandPixels / double(rasterSize.y);
  precise double d;
  if (plane == 0) {
    d = v.w - v.z;
  } else if (plane == 1) {
    d = v.z;
  } else if (plane == 2) {
    d = guardX * v.w - v.x;
  } else if (plane == 3) {
    d = guardX * v.w + v.x;
  } else if (plane == 4) {
    d = guardY * v.w - v.y;
  } else {
    d = guardY * v.w + v.y;
  }
  return d;
}

// A clip position's snapped screen position (x, y) and depth key z / w.
dvec3 Snap(dvec4 v) {
  precise double invW = 1.0LF / v.w;
  precise double sx = (v.x * invW * 0.5LF + 0.5LF) * double(rasterSize.x);
  precise double sy = (0.5LF - v.y * invW * 0.5LF) * double(rasterSize.y);
  precise double key = v.z * invW;
  return dvec3(RoundHalfAwayToInt(sx * double(kSubPixelScale)), RoundHalfAwayToInt(sy * double(kSubPixelScale)), key);
}

// SetUpScreenTriangle: false where culled (zero area, a back face `cull` culls, no pixel centre in
// the target).
bool SetUp(dvec3 s0, dvec3 s1, dvec3 s2, bool cull, out ScreenTriangle t) {
  t.x = ivec4(0);
  t.y = ivec4(0);
  t.key = dvec4(0.0LF);
  dvec3 v[3] = dvec3[3](s0, s1, s2);
  precise double area2 = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[1].y - v[0].y) * (v[2].x - v[0].x);
  if (area2 == 0.0LF) return false;
  // Counter-clockwise front faces are clockwise on the y-down screen: negative area.
  const bool backFacing = area2 > 0.0LF;
  if (backFacing && cull) return false;
  if (!backFacing) {
    const dvec3 swap = v[1];
    v[1] = v[2];
    v[2] = swap;
    area2 = -area2;
  }
  const int minSx = int(min(min(v[0].x, v[1].x), v[2].x)), maxSx = int(max(max(v[0].x, v[1].x), v[2].x));
  const int minSy = int(min(min(v[0].y, v[1].y), v[2].y)), maxSy = int(max(max(v[0].y, v[1].y), v[2].y));
  // Pixels whose centre sample lies inside the snapped bounds (>> is a floor division).
  const int minX = max(0, (minSx - kHalfPixel + kSubPixelScale - 1) >> 8);
  const int maxX = min(rasterSize.x - 1, (maxSx - kHalfPixel) >> 8);
  const int minY = max(0, (minSy - kHalfPixel + kSubPixelScale - 1) >> 8);
  const int maxY = min(rasterSize.y - 1, (maxSy - kHalfPixel) >> 8);
  if (minX > maxX || minY > maxY) return false;
  t.x = ivec4(int(v[0].x), int(v[1].x), int(v[2].x), 0);
  t.y = ivec4(int(v[0].y), int(v[1].y), int(v[2].y), 0);
  // The depth key's plane in pixel units through the snapped vertices.
  const double scale = double(kSubPixelScale);
  precise double x10 = (v[1].x - v[0].x) / scale, y10 = (v[1].y - v[0].y) / scale;
  precise double x20 = (v[2].x - v[0].x) / scale, y20 = (v[2].y - v[0].y) / scale;
  precise double k10 = v[1].z - v[0].z, k20 = v[2].z - v[0].z;
  precise double det = area2 / (scale * scale);
  precise double keyDx = (k10 * y20 - k20 * y10) / det;
  precise double keyDy = (k20 * x10 - k10 * x20) / det;
  precise double x0 = v[0].x / scale, y0 = v[0].y / scale;
  precise double keyAtOrigin = v[0].z + keyDx * (0.5LF - x0) + keyDy * (0.5LF - y0);
  t.key = dvec4(keyAtOrigin, keyDx, keyDy, 0.0LF);
  return true;
}

void main() {
  const int triangle = int(gl_GlobalInvocationID.x) + rowLength * int(gl_GlobalInvocationID.y);
  if (int(gl_GlobalInvocationID.x) >= rowLength || triangle >= triangleCount) return;
  const Material material = materials[triangleMaterial[triangle]];
  const bool cull = (cullBackFaces != 0 && material.roughnessCutoffTwoSided.z == 0.0) || closedCulled[triangle] != 0u;
  const uint first = uint(triangle) * uint(kMaxPieces);
  dvec4 polygon[2][9];
  int outsideAll = 63, outsideAny = 0;
  for (int k = 0; k < 3; ++k) {
    polygon[0][k] = dvec4(Transform(viewProjection, MeshPosition(indices[3 * triangle + k])));
    int outside = 0;
    for (int p = 0; p < kPlanes; ++p) outside |= ClipDistance(polygon[0][k], p) >= 0.0LF ? 0 : 1 << p;
    outsideAll &= outside;
    outsideAny |= outside;
  }
  uint count = 0u;
  if (outsideAll != 0) {
    // Wholly outside one plane.
  } else if (outsideAny == 0) {
    ScreenTriangle t;
    if (SetUp(Snap(polygon[0][0]), Snap(polygon[0][1]), Snap(polygon[0][2]), cull, t)) pieces[first + count++] = t;
  } else {
    // Sutherland-Hodgman against each plane in turn, then a fan from the first vertex.
    int vertices = 3, current = 0;
    for (int p = 0; p < kPlanes && vertices >= 3; ++p) {
      int written = 0;
      for (int i = 0; i < vertices; ++i) {
        const dvec4 a = polygon[current][i], b = polygon[current][(i + 1) % vertices];
        const double da = ClipDistance(a, p), db = ClipDistance(b, p);
        if (da >= 0.0LF) polygon[current ^ 1][written++] = a;
        if ((da >= 0.0LF) != (db >= 0.0LF)) {
          precise double t = da / (da - db);
          precise dvec4 between = a + (b - a) * t;
          polygon[current ^ 1][written++] = between;
        }
      }
      vertices = written;
      current ^= 1;
    }
    for (int i = 1; i + 1 < vertices; ++i) {
      ScreenTriangle t;
      if (SetUp(Snap(polygon[current][0]), Snap(polygon[current][i]), Snap(polygon[current][i + 1]), cull, t))
        pieces[first + count++] = t;
    }
  }
  pieceCount[triangle] = count;
}
