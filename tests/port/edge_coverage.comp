// Edge coverage (docs/pipeline.md §Edge coverage and anti-aliasing, its "GPU matching rules"): a
// full-screen pass over the visibility buffer's triangles and word 2's depths that writes each
// pixel's coverage word from the front triangle's own screen-space edges, in double as the oracle
// computes it (GLSL 4.50 has double): the codes are then the oracle's, where float32 moved 0.2-0.5 %
// of the words (tests/port/README.md). Each pixel weighs its four pairs itself: a pair is computed
// by both its pixels, which costs a little work and needs no second pass.
// Included after common.glsl and surface.glsl (the mesh's positions, indices and materials).
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Triangles { uint triangleAt[]; };  // the visibility buffer's
layout(std430, binding = 1) readonly buffer Word2 { uint word2[]; };
layout(std430, binding = 2) writeonly buffer Coverage { uint coverage[]; };

// The camera's view-projection (glm's float matrix, widened to double exactly).
uniform mat4 viewProjection;

const uint kNoTriangle = 0xFFFFFFFFu;
// 1 + kEdgeDepthJump (0.02f) rounded to float32, by bit pattern.
const float kEdgeDepthRatio = uintBitsToFloat(0x3F828F5Cu);

uint TriangleAt(ivec2 pixel) { return triangleAt[pixel.y * imageSize.x + pixel.x]; }
float DepthAt(ivec2 pixel) { return uintBitsToFloat(word2[pixel.y * imageSize.x + pixel.x]); }

// GeometricEdge: two triangles of one material whose depths are within 2 % meet on one surface.
// The depths are finite (both pixels have geometry), so std::min and std::max are GLSL's.
bool GeometricEdge(uint a, uint b, float depthA, float depthB) {
  if (a == b) return false;
  if (a == kNoTriangle || b == kNoTriangle) return true;
  if (triangleMaterial[a] != triangleMaterial[b]) return true;
  precise float limit = min(depthA, depthB) * kEdgeDepthRatio;
  return max(depthA, depthB) > limit;
}

// A vertex in homogeneous pixel coordinates (x w, y w, w): glm's dmat4 * dvec4 order,
// (m0 x + m1 y) + (m2 z + m3), then the screen mapping before the division by w.
dvec3 HomogeneousPixel(uint vertex) {
  const dmat4 m = dmat4(viewProjection);
  const dvec3 p = dvec3(MeshPosition(vertex));
  precise dvec4 xy = m[0] * p.x + m[1] * p.y;
  precise dvec4 zw = m[2] * p.z + m[3];
  precise dvec4 clip = xy + zw;
  precise double x = (0.5LF * clip.x + 0.5LF * clip.w) * double(imageSize.x);
  precise double y = (0.5LF * clip.w - 0.5LF * clip.y) * double(imageSize.y);
  return dvec3(x, y, clip.w);
}

// glm's cross and dot in double: surface.glsl's Cross3 and common.glsl's Dot3 for dvec3.
dvec3 Cross3(dvec3 a, dvec3 b) {
  precise dvec3 c = dvec3(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
  return c;
}
double Dot3(dvec3 a, dvec3 b) {
  precise double xy = a.x * b.x + a.y * b.y;
  precise double xyz = xy + a.z * b.z;
  return xyz;
}

// BoxCoverage: the area of the unit pixel square on the positive side of the line at signed
// distance `d` from its centre, with unit normal (nx, ny).
double BoxCoverage(double d, double nx, double ny) {
  const double a = max(abs(nx), abs(ny)), b = min(abs(nx), abs(ny));
  precise double h1 = 0.5LF * (a - b), h2 = 0.5LF * (a + b);
  const double t = abs(d);
  precise double halfArea;
  if (t >= h2) {
    halfArea = 0.5LF;
  } else if (t <= h1) {
    halfArea = t / a;
  } else {
    precise double foot = h2 - t;
    halfArea = h1 / a + (b * b - foot * foot) / (2.0LF * a * b);
  }
  precise double result = d >= 0.0LF ? 0.5LF + halfArea : 0.5LF - halfArea;
  return result;
}

// The weights of pixel `a` and its right (alongX) or lower neighbour b: x the share of a covered
// by b's surface, y that of b covered by a's; 0 where no edge of the front triangle separates
// their centres along this pair's minor axis.
dvec2 PairWeights(ivec2 a, bool alongX) {
  const ivec2 b = a + (alongX ? ivec2(1, 0) : ivec2(0, 1));
  const uint triangleA = TriangleAt(a), triangleB = TriangleAt(b);
  if (triangleA == triangleB) return dvec2(0.0LF);
  const float depthA = DepthAt(a), depthB = DepthAt(b);
  if (!GeometricEdge(triangleA, triangleB, depthA, depthB)) return dvec2(0.0LF);
  // The nearer surface; the background never is, and a tie takes a.
  const bool aFront = triangleB == kNoTriangle || (triangleA != kNoTriangle && depthA <= depthB);
  const uint front = aFront ? triangleA : triangleB;
  const dvec3 centreA = dvec3(dvec2(a) + 0.5LF, 1.0LF), centreB = dvec3(dvec2(b) + 0.5LF, 1.0LF);
  const dvec3 frontCentre = aFront ? centreA : centreB, backCentre = aFront ? centreB : centreA;
  dvec3 h[3];
  for (int i = 0; i < 3; ++i) h[i] = HomogeneousPixel(indices[3u * front + uint(i)]);
  // The edge the segment from the front centre leaves the triangle through: the first crossing.
  dvec3 line = dvec3(0.0LF);
  double lineFront = 0.0LF, lineBack = 0.0LF, exit = 2.0LF;
  for (int i = 0; i < 3; ++i) {
    dvec3 edge = Cross3(h[i], h[(i + 1) % 3]);
    double eFront = Dot3(edge, frontCentre), eBack = Dot3(edge, backCentre);
    if (eFront < 0.0LF) {
      edge = -edge;
      eFront = -eFront;
      eBack = -eBack;
    }
    if (!(eBack < 0.0LF)) continue;
    precise double t = eFront / (eFront - eBack);
    if (t < exit) {
      exit = t;
      line = edge;
      lineFront = eFront;
      lineBack = eBack;
    }
  }
  precise double length = sqrt(line.x * line.x + line.y * line.y);
  if (exit > 1.0LF || !(length > 0.0LF) || isinf(length)) return dvec2(0.0LF);
  precise double nx = line.x / length, ny = line.y / length;
  if (alongX ? abs(nx) < abs(ny) : abs(ny) <= abs(nx)) return dvec2(0.0LF);
  precise double frontOutside = 1.0LF - BoxCoverage(lineFront / length, nx, ny);
  const double backInside = BoxCoverage(lineBack / length, nx, ny);
  return aFront ? dvec2(frontOutside, backInside) : dvec2(backInside, frontOutside);
}

// A weight as the word's byte: 1/256 units, rounded, at most 255.
uint WeightCode(double w) {
  precise double scaled = floor(w * 256.0LF + 0.5LF);
  return uint(min(255.0LF, scaled));
}

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;
  uint code[4] = uint[4](0u, 0u, 0u, 0u);  // left, right, up, down
  if (pixel.x > 0) code[0] = WeightCode(PairWeights(pixel - ivec2(1, 0), true).y);
  if (pixel.x + 1 < imageSize.x) code[1] = WeightCode(PairWeights(pixel, true).x);
  if (pixel.y > 0) code[2] = WeightCode(PairWeights(pixel - ivec2(0, 1), false).y);
  if (pixel.y + 1 < imageSize.y) code[3] = WeightCode(PairWeights(pixel, false).x);
  const uint sum = code[0] + code[1] + code[2] + code[3];
  // Overlapping shares (a corner, a feature thinner than the pixel) scaled to the whole pixel.
  if (sum > 256u)
    for (int k = 0; k < 4; ++k) code[k] = code[k] * 256u / sum;
  coverage[pixel.y * imageSize.x + pixel.x] = code[0] | code[1] << 8 | code[2] << 16 | code[3] << 24;
}
