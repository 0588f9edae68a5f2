// §Blocker search: the PCSS blocker search of every G-buffer pixel against the shadow map, with the
// normal offset, receiver-plane depth and slope-scaled bias of §Bias, into word 3 (hard flag in bit
// 31, the mean blocker distance's float bits in 0-30; 0 = lit). BlockerSearchRowScalar
// (passes/shadow_map.cpp) is the definition.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Word1 { uint word1[]; };
layout(std430, binding = 1) readonly buffer Word2 { uint word2[]; };
layout(std430, binding = 2) readonly buffer ShadowMap { float depthKey[]; };
layout(std430, binding = 3) writeonly buffer Word3 { uint word3[]; };

const int kMaxTaps = 256;
uniform vec2 pattern[kMaxTaps];  // Vogel's spiral, tap 0 the centre
uniform int taps;
uniform int lightOrthographic;
uniform int resolution;  // of the map, square
uniform float lightNear, lightFar;
uniform vec2 lightHalf;  // the light view's halfX, halfY
uniform vec2 texel;      // texelX, texelY: orthographic metres, perspective per metre of depth
uniform vec2 invTexel;
uniform float tanAngularRadius;  // directional
uniform float lightRadius;       // spot
uniform float maxBlockerDistance;

const uint kShadowLit = 0u;
const float kNormalOffsetTexels = 1.0, kConstantBiasTexels = 0.25, kSlopeBiasTexels = 0.25;
const float kMaxSlope = 20.0, kMinFacing = 1e-6;

// std::max(a, b) = a < b ? b : a and std::min(a, b) = b < a ? b : a.
float StdMax(float a, float b) { return a < b ? b : a; }
float StdMin(float a, float b) { return b < a ? b : a; }

// ViewProjection::DepthFromKey of the light's view.
float DepthFromKey(float key) {
  precise float orthographic = lightNear + (1.0 - key) * (lightFar - lightNear);
  precise float perspective = lightNear / key;
  return lightOrthographic != 0 ? orthographic : perspective;
}

uint SearchBlockers(vec3 p, uint normalWord) {
  const bool ortho = lightOrthographic != 0;
  const float size = float(resolution);
  const vec3 n = RotateToLight(UnpackNormal(normalWord));
  const float depth = -p.z;
  if (!(depth > lightNear)) return kShadowLit;
  // Distance from the light along its ray: orthographic, from the view's origin plane.
  const float distance = ortho ? depth : sqrt(Dot3(p, p));
  precise vec3 toLightSpot = -p / distance;
  const vec3 toLight = ortho ? vec3(0.0, 0.0, 1.0) : toLightSpot;
  const float cosAngle = Dot3(n, toLight);
  precise float sinSquared = 1.0 - cosAngle * cosAngle;
  const float sinAngle = sqrt(StdMax(0.0, sinSquared));
  precise float cosScaled = cosAngle * kMaxSlope;
  precise float tangent = sinAngle / cosAngle;
  const float slope = cosScaled > sinAngle ? tangent : kMaxSlope;
  precise float texelSize = StdMax(texel.x, texel.y) * (ortho ? 1.0 : depth);
  precise vec3 biased = p + n * (kNormalOffsetTexels * texelSize * sinAngle);
  const float biasedDepth = -biased.z;
  if (!(biasedDepth > lightNear)) return kShadowLit;
  precise float toUnitDepth = ortho ? 1.0 : 1.0 / biasedDepth;
  precise vec2 centre = vec2((biased.x * toUnitDepth + lightHalf.x) * invTexel.x,
                             (lightHalf.y - biased.y * toUnitDepth) * invTexel.y);
  if (!(centre.x >= 0.0 && centre.x < size && centre.y >= 0.0 && centre.y < size)) return kShadowLit;
  precise float bias = texelSize * (kConstantBiasTexels + kSlopeBiasTexels * slope);

  // Search radius in texels.
  precise vec2 radius;
  if (ortho) {
    precise float world = StdMin(depth - lightNear, maxBlockerDistance) * tanAngularRadius;
    radius = vec2(world * invTexel.x, world * invTexel.y);
  } else {
    const float nearest = StdMax(lightNear, depth - maxBlockerDistance);
    precise float r = lightRadius * (depth - nearest) / (depth * nearest) * invTexel.x;
    radius = vec2(r);
  }
  radius = vec2(StdMin(radius.x, size), StdMin(radius.y, size));

  // The receiver's tangent plane along each tap texel's ray.
  precise float m0 = n.x * (0.5 * texel.x - lightHalf.x) + n.y * (lightHalf.y - 0.5 * texel.y);
  precise float mx = n.x * texel.x;
  precise float my = -n.y * texel.y;
  precise float c = n.x * biased.x + n.y * biased.y;
  precise float nxy = n.x * n.x + n.y * n.y;
  const float minFacing = StdMax(sqrt(nxy) / kMaxSlope, kMinFacing);
  precise float invFacing = ortho ? 1.0 / StdMax(n.z, minFacing) : 0.0;

  bool hardShadow = false;
  int blockers = 0;
  precise float blockerDistanceSum = 0.0;
  for (int i = 0; i < taps; ++i) {
    precise vec2 tap = centre + pattern[i] * radius;
    if (!(tap.x >= 0.0 && tap.x < size && tap.y >= 0.0 && tap.y < size)) continue;
    const int tx = int(tap.x), ty = int(tap.y);
    const float key = depthKey[ty * resolution + tx];
    if (key == 0.0) continue;  // nothing drawn: no blocker
    precise float m = m0 + mx * float(tx) + my * float(ty);
    precise float planeOrtho = biasedDepth + (m - c) * invFacing;
    precise float planeSpot = biasedDepth + (biasedDepth * m - c) / StdMax(n.z - m, minFacing);
    const float planeDepth = ortho ? planeOrtho : planeSpot;
    const float tapDepth = DepthFromKey(key);
    precise float limit = planeDepth - bias;
    if (!(tapDepth < limit)) continue;
    hardShadow = hardShadow || i == 0;
    ++blockers;
    if (ortho) {
      blockerDistanceSum += tapDepth;
    } else {
      precise vec3 ray = vec3((float(tx) + 0.5) * texel.x - lightHalf.x, lightHalf.y - (float(ty) + 0.5) * texel.y, 1.0);
      precise float along = tapDepth * sqrt(Dot3(ray, ray));
      blockerDistanceSum += along;
    }
  }
  if (blockers == 0) return kShadowLit;
  precise float mean = blockerDistanceSum / float(blockers);
  precise float average = StdMax(0.0, distance - mean);
  return floatBitsToUint(average) | (hardShadow ? 0x80000000u : 0u);
}

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;
  const int i = pixel.y * imageSize.x + pixel.x;
  const float depth = uintBitsToFloat(word2[i]);
  word3[i] = depth < kBackgroundDepth ? SearchBlockers(ReceiverPosition(pixel, depth), word1[i]) : kShadowLit;
}
