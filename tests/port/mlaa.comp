// Morphological anti-aliasing (docs/pipeline.md §Morphological anti-aliasing), one dispatch per step
// (a `stage` uniform): the luma, the edge bits, each pixel's run weights, the coverage words. Each
// invocation follows the runs through its own pixel's left and top edges to both ends (SMAA's search
// without its limit), so it writes its own weight word and nothing else: the words do not depend on
// the order invocations run in.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Image { float image[]; };  // three planes
layout(std430, binding = 1) buffer Luma { float luma[]; };
layout(std430, binding = 2) buffer Edges { uint edges[]; };
layout(std430, binding = 3) buffer Weights { uint weights[]; };
layout(std430, binding = 4) writeonly buffer Coverage { uint coverage[]; };

uniform int stage;  // 0 luma, 1 edges, 2 weights, 3 coverage
uniform float exposureScale;  // exp2(exposureEv), computed once per frame
uniform float threshold;

const uint kLeftEdge = 1u, kTopEdge = 2u;
// Rec. 709's luminance weights as float32, by bit pattern: 0.2126f, 0.7152f, 0.0722f.
const float kLumaR = uintBitsToFloat(0x3E59B3D0u);
const float kLumaG = uintBitsToFloat(0x3F371759u);
const float kLumaB = uintBitsToFloat(0x3D93DD98u);

int Index(int x, int y) { return y * imageSize.x + x; }
float LumaAt(int x, int y) { return luma[Index(x, y)]; }
uint EdgesAt(int x, int y) { return edges[Index(x, y)]; }
bool HasEdge(int x, int y, uint bit) { return (edges[Index(x, y)] & bit) != 0u; }

// L = sqrt(t / (1 + t)), t the sanitised luminance times the exposure; each operation correctly
// rounded (llvmpipe's division and square root are, tests/port/README.md).
void WriteLuma(int x, int y) {
  const int plane = imageSize.x * imageSize.y, i = Index(x, y);
  precise float luminance = (kLumaR * image[i] + kLumaG * image[i + plane]) + kLumaB * image[i + 2 * plane];
  precise float exposed = luminance * exposureScale;
  const float t = SanitizeRadiance(exposed);
  precise float perceptual = sqrt(t / (1.0 + t));
  luma[i] = perceptual;
}

// The edge bits of (x, y); a neighbour past the border is the nearest pixel along that direction.
// Differences of finite luma are finite and >= 0, so GLSL's max is std::max.
void WriteEdges(int x, int y) {
  const int left = max(x - 1, 0), leftLeft = x > 1 ? x - 2 : left, right = min(x + 1, imageSize.x - 1);
  const int up = max(y - 1, 0), upUp = y > 1 ? y - 2 : up, down = min(y + 1, imageSize.y - 1);
  const float l = LumaAt(x, y);
  precise float toLeft = abs(l - LumaAt(left, y)), toUp = abs(l - LumaAt(x, up));
  precise float toRight = abs(l - LumaAt(right, y)), toDown = abs(l - LumaAt(x, down));
  precise float leftToLeft = abs(LumaAt(left, y) - LumaAt(leftLeft, y));
  precise float upToUp = abs(LumaAt(x, up) - LumaAt(x, upUp));
  const float largest = max(max(max(toLeft, toUp), max(toRight, toDown)), max(leftToLeft, upToUp));
  const bool leftEdge = toLeft >= threshold && largest <= 2.0 * toLeft;
  const bool topEdge = toUp >= threshold && largest <= 2.0 * toUp;
  edges[Index(x, y)] = (leftEdge ? kLeftEdge : 0u) | (topEdge ? kTopEdge : 0u);
}

// A run end's height from whether the edge steps to the first side there and to the second: +1,
// -1, or 0 for neither or both.
int EndHeight(bool toFirstSide, bool toSecondSide) {
  if (toFirstSide == toSecondSide) return 0;
  return toFirstSide ? 1 : -1;
}

// The area numerator, in 1/(8 n), of one half of the silhouette over the pixel `k` pixels from that
// half's end. 32-bit integers hold it exactly for runs up to 65,535 pixels, past the largest image.
uint HalfRunArea(uint n, uint k) {
  const uint a = 2u * k;
  if (a >= n) return 0u;
  const uint b = min(a + 2u, n);
  return 2u * (b - a) * n - (b * b - a * a);
}

// MlaaRunWeights: the codes of pixel k of a run of n whose ends' heights are hs and he, (first
// side's, second side's); (0, 0) for a straight run.
uvec2 RunWeights(uint n, uint k, int hs, int he) {
  uint area[2] = uint[2](0u, 0u);
  if (hs != 0) area[hs > 0 ? 0 : 1] += HalfRunArea(n, k);
  if (he != 0) area[he > 0 ? 0 : 1] += HalfRunArea(n, n - 1u - k);
  return uvec2((64u * area[0] + n) / (2u * n), (64u * area[1] + n) / (2u * n));
}

// Whether an edge crosses row y's horizontal edge at the left border of pixel x.
bool CrossesRow(int x, int y) { return ((EdgesAt(x, y - 1) | EdgesAt(x, y)) & kLeftEdge) != 0u; }
// Whether one crosses column x's vertical edge at the top border of row y.
bool CrossesColumn(int x, int y) { return ((EdgesAt(x - 1, y) | EdgesAt(x, y)) & kTopEdge) != 0u; }

// The height of a horizontal run's end in row y at the left border of column c (0 < c < width),
// `beyond` the column past the end: up where an edge crosses above and (beyond, y - 1) has a top
// edge, down where one crosses below and (beyond, y + 1) has one.
int RowEndHeight(int c, int beyond, int y) {
  if (c == 0 || c >= imageSize.x) return 0;
  const bool up = HasEdge(c, y - 1, kLeftEdge) && HasEdge(beyond, y - 1, kTopEdge);
  const bool down = HasEdge(c, y, kLeftEdge) && y + 1 < imageSize.y && HasEdge(beyond, y + 1, kTopEdge);
  return EndHeight(up, down);
}

// The height of a vertical run's end in column x at the top border of row r (0 < r < height),
// `beyond` the row past the end: left where an edge crosses on the left and (x - 1, beyond) has a
// left edge, right where one crosses on the right and (x + 1, beyond) has one.
int ColumnEndHeight(int x, int r, int beyond) {
  if (r == 0 || r >= imageSize.y) return 0;
  const bool left = HasEdge(x - 1, r, kTopEdge) && HasEdge(x - 1, beyond, kLeftEdge);
  const bool right = HasEdge(x, r, kTopEdge) && x + 1 < imageSize.x && HasEdge(x + 1, beyond, kLeftEdge);
  return EndHeight(left, right);
}

// The weight word of (x, y): bytes 2-3 from the horizontal run its top edge belongs to, bytes 0-1
// from the vertical run its left edge belongs to.
void WriteWeights(int x, int y) {
  uint word = 0u;
  if (y >= 1 && HasEdge(x, y, kTopEdge)) {
    int a = x, b = x;
    while (a > 0 && HasEdge(a - 1, y, kTopEdge) && !CrossesRow(a, y)) --a;
    while (b + 1 < imageSize.x && HasEdge(b + 1, y, kTopEdge) && !CrossesRow(b + 1, y)) ++b;
    const uvec2 codes = RunWeights(uint(b - a + 1), uint(x - a), RowEndHeight(a, a - 1, y), RowEndHeight(b + 1, b + 1, y));
    word |= codes.x << 16 | codes.y << 24;
  }
  if (x >= 1 && HasEdge(x, y, kLeftEdge)) {
    int a = y, b = y;
    while (a > 0 && HasEdge(x, a - 1, kLeftEdge) && !CrossesColumn(x, a)) --a;
    while (b + 1 < imageSize.y && HasEdge(x, b + 1, kLeftEdge) && !CrossesColumn(x, b + 1)) ++b;
    const uvec2 codes =
        RunWeights(uint(b - a + 1), uint(y - a), ColumnEndHeight(x, a, a - 1), ColumnEndHeight(x, b + 1, b + 1));
    word |= codes.x | codes.y << 8;
  }
  weights[Index(x, y)] = word;
}

// The coverage word of (x, y), one axis only: the horizontal pair where its larger share beats the
// vertical pair's, else the vertical pair.
void WriteCoverage(int x, int y) {
  const uint own = weights[Index(x, y)];
  const uint left = (own >> 8) & 255u, right = x + 1 < imageSize.x ? weights[Index(x + 1, y)] & 255u : 0u;
  const uint up = own >> 24, down = y + 1 < imageSize.y ? (weights[Index(x, y + 1)] >> 16) & 255u : 0u;
  const bool horizontal = max(left, right) > max(up, down);
  coverage[Index(x, y)] = horizontal ? left | right << 8 : up << 16 | down << 24;
}

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;
  if (stage == 0) {
    WriteLuma(pixel.x, pixel.y);
  } else if (stage == 1) {
    WriteEdges(pixel.x, pixel.y);
  } else if (stage == 2) {
    WriteWeights(pixel.x, pixel.y);
  } else {
    WriteCoverage(pixel.x, pixel.y);
  }
}
