// §Shadow filter (SSABSS): `stage` 0 sets up every pixel (view position, normal, hard value and its
// kernel), 1 blurs the hard values along each pixel's major axis, 2 blurs that along its minor
// axis into the visibility. Every tile is blurred: the oracle's blur-area control skips only tiles
// whose blur gives their hard values bit for bit (RunShadowFilterEveryTile is its reference).
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Word1 { uint word1[]; };
layout(std430, binding = 1) readonly buffer Word2 { uint word2[]; };
layout(std430, binding = 2) readonly buffer Word3 { uint word3[]; };
// Per pixel, plane after plane: position xyz, normal xyz, hard, major axis xy, major and minor
// half-lengths (11 planes).
layout(std430, binding = 3) buffer SetUp { float setUp[]; };
layout(std430, binding = 4) buffer MajorPass { float majorPass[]; };
layout(std430, binding = 5) writeonly buffer Visibility { float visibility[]; };

uniform int stage;
uniform int filterKind;  // 0 hard, 1 SSPCSS, 2 SSABSS
uniform int blurTaps;    // 0: one per pixel of the length
uniform float maxRadius;
uniform float pixelsPerMetreAtUnitDepth;  // height / (2 tanHalfY)
// The shadowed light in view space.
uniform int lightIsSpot;
uniform vec3 lightPosition;
uniform float lightRadius, lightTanAngularRadius;

const float kMinNormalDot = 0.8, kMaxPlaneDistance = 0.02, kMinProjectedNormal = 1e-4;
const float kMinLightToBlocker = 1e-3, kMinBlurRadius = 0.5;
const int kPlanes = 11;

float StdMax(float a, float b) { return a < b ? b : a; }
float StdMin(float a, float b) { return b < a ? b : a; }

int Pixels() { return imageSize.x * imageSize.y; }
float Plane(int plane, int i) { return setUp[plane * Pixels() + i]; }
vec3 Position(int i) { return vec3(Plane(0, i), Plane(1, i), Plane(2, i)); }
vec3 Normal(int i) { return vec3(Plane(3, i), Plane(4, i), Plane(5, i)); }

bool Background(float depth) { return !(depth > 0.0 && depth < kBackgroundDepth); }

// PCSS penumbra half-width in pixels, clamped; non-finite (0 * inf) gives 0.
float PenumbraRadius(vec3 position, float depth, float blockerDistance) {
  precise float width;
  if (lightIsSpot != 0) {
    precise vec3 toLightVector = lightPosition - position;
    const float toLight = sqrt(Dot3(toLightVector, toLightVector));
    precise float gap = toLight - blockerDistance;
    width = blockerDistance * 2.0 * lightRadius / StdMax(gap, kMinLightToBlocker);
  } else {
    width = blockerDistance * 2.0 * lightTanAngularRadius;
  }
  precise float radius = 0.5 * width * (pixelsPerMetreAtUnitDepth / depth);
  if (!(radius > 0.0)) return 0.0;
  return StdMin(radius, maxRadius);
}

void SetUpPixel(ivec2 pixel, int i) {
  const float depth = uintBitsToFloat(word2[i]);
  vec3 position = vec3(0.0), normal = vec3(0.0), major = vec3(1.0, 0.0, 0.0);
  float hard = 1.0, majorLength = 0.0, minorLength = 0.0;
  if (!Background(depth)) {
    const vec3 ray = PixelRayDirection(vec2(pixel) + 0.5);
    precise vec3 p = depth * ray;
    position = p;
    normal = UnpackNormal(word1[i]);
    hard = (word3[i] >> 31) != 0u ? 0.0 : 1.0;
    const float radius = PenumbraRadius(position, depth, uintBitsToFloat(word3[i] & 0x7FFFFFFFu));
    if (filterKind != 0 && !(radius < kMinBlurRadius)) {
      majorLength = radius;
      minorLength = radius;
      if (filterKind == 2) {
        const vec3 n = normal;
        const float d = -position.z;
        // The derivative of the perspective projection along n, times d.
        precise vec2 projected = vec2(n.x + position.x / d * n.z, -(n.y + position.y / d * n.z));
        precise float lengthSquared = projected.x * projected.x + projected.y * projected.y;
        const float length = sqrt(lengthSquared);
        if (!(length < kMinProjectedNormal)) {
          precise vec2 m = projected / length;
          const float facing = abs(Dot3(n, -position)) / sqrt(Dot3(position, position));
          major = vec3(m.y, -m.x, 0.0);
          precise float minor = radius * facing;
          minorLength = minor;
        }
      }
    }
  }
  const float values[kPlanes] = float[kPlanes](position.x, position.y, position.z, normal.x, normal.y, normal.z,
                                               hard, major.x, major.y, majorLength, minorLength);
  for (int plane = 0; plane < kPlanes; ++plane) setUp[plane * Pixels() + i] = values[plane];
}

bool Accepts(int centre, int tap) {
  const vec3 cp = Position(centre), cn = Normal(centre), tp = Position(tap), tn = Normal(tap);
  precise vec3 offset = tp - cp;
  precise float limit = kMaxPlaneDistance * -cp.z;
  return tp.z < 0.0 && Dot3(tn, cn) > kMinNormalDot && abs(Dot3(cn, offset)) < limit;
}

// One 1-D box pass at `pixel` along `direction`, half-length `length`, over plane `source` of the
// set-up (the hard values) or the major pass.
float Blur1D(ivec2 pixel, int centre, bool fromMajorPass, vec2 direction, float length) {
  const float own = fromMajorPass ? majorPass[centre] : Plane(6, centre);
  if (!(Position(centre).z < 0.0) || !(length >= kMinBlurRadius)) return own;
  const int count = blurTaps > 0 ? blurTaps : int(ceil(length - 0.5));
  precise float spacing = blurTaps > 0 ? length / (float(blurTaps) + 0.5) : 1.0;
  precise float sum = own;
  precise float weightSum = 1.0;
  for (int k = 1; k <= count; ++k) {
    precise float t = float(k) * spacing;
    precise float share = length - (t - 0.5);
    const float weight = blurTaps > 0 ? 1.0 : StdMin(1.0, share);
    for (int s = 0; s < 2; ++s) {
      const float side = s == 0 ? -1.0 : 1.0;
      precise float fx = float(pixel.x) + 0.5 + side * t * direction.x;
      precise float fy = float(pixel.y) + 0.5 + side * t * direction.y;
      const float sx = floor(fx), sy = floor(fy);
      if (!(sx >= 0.0 && sy >= 0.0 && sx < float(imageSize.x) && sy < float(imageSize.y))) continue;
      const int tap = int(sy) * imageSize.x + int(sx);
      if (!Accepts(centre, tap)) continue;
      const float value = fromMajorPass ? majorPass[tap] : Plane(6, tap);
      sum += weight * value;
      weightSum += weight;
    }
  }
  precise float blurred = sum / weightSum;
  return blurred;
}

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;
  const int i = pixel.y * imageSize.x + pixel.x;
  if (stage == 0) {
    SetUpPixel(pixel, i);
  } else if (stage == 1) {
    majorPass[i] = Blur1D(pixel, i, false, vec2(Plane(7, i), Plane(8, i)), Plane(9, i));
  } else {
    visibility[i] = Blur1D(pixel, i, true, vec2(-Plane(8, i), Plane(7, i)), Plane(10, i));
  }
}
