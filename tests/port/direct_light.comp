// Direct light (docs/pipeline.md §Direct light): every light of the scene on every G-buffer pixel,
// Lambert diffuse plus GGX specular over the light's disk (core/lighting.h's DiskLightBrdfCosine,
// its operations in its order), the shadowed light's term times the shadow filter's visibility.
// Background pixels get the background radiance.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Word0 { uint word0[]; };
layout(std430, binding = 1) readonly buffer Word1 { uint word1[]; };
layout(std430, binding = 2) readonly buffer Word2 { float depth[]; };
layout(std430, binding = 3) readonly buffer Visibility { float visibility[]; };  // of the shadowed light
layout(std430, binding = 4) writeonly buffer Direct { float direct[]; };         // three planes

// A light as core/lighting.h's PrepareLights gives it, in view space.
struct Light {
  vec4 positionIsSpot;       // spot: emitter centre; w: 1 for a spot, 0 for a directional light
  vec4 directionRadius;      // unit; directional: travel direction, spot: cone axis; w: spot radius
  vec4 powerTanRadius;       // directional: irradiance, spot: intensity; w: directional tan(angular radius)
  vec4 cone;                 // spot: x cos(outer), y 1 / max(cos(inner) - cos(outer), 1e-4)
};
layout(std430, binding = 5) readonly buffer Lights { Light lights[]; };
uniform int lightCount;
uniform int shadowedLight;  // index into lights; -1: no light is shadowed
uniform vec3 background;

const float kPi = 3.14159265358979323846;
const float kMinGgxAlpha = 0.045 * 0.045;

float Clamp01(float x) { return x < 0.0 ? 0.0 : (1.0 < x ? 1.0 : x); }  // std::clamp(x, 0, 1)

float GgxDistribution(float nDotH, float alpha) {
  precise float a2 = alpha * alpha;
  precise float f = nDotH * nDotH * (a2 - 1.0) + 1.0;
  precise float d = a2 / (kPi * f * f);
  return d;
}

// Height-correlated Smith visibility V = G / (4 n.l n.v) (Heitz 2014), times n.l: divided through
// by n.l, which stays finite where both cosines are denormal.
float SmithGgxCorrelatedVisibilityCosine(float nDotV, float nDotL, float alpha) {
  precise float a2 = alpha * alpha;
  precise float lambdaV = sqrt(nDotV * nDotV * (1.0 - a2) + a2);
  precise float lambdaL = sqrt(nDotL * nDotL * (1.0 - a2) + a2);
  precise float v = 0.5 / (lambdaV + (nDotV / nDotL) * lambdaL);
  return v;
}

vec3 SchlickFresnel(float vDotH, vec3 f0) {
  precise float m = 1.0 - vDotH;
  precise float m2 = m * m;
  precise vec3 f = f0 + (vec3(1.0) - f0) * (m2 * m2 * m);
  return f;
}

// The representative direction: r where it passes through the disk of `radius` at distance 1 along
// l, else the point whose distance from r is sqrt(T^2 - radius^2), T r's distance from the centre
// (an area-preserving remap); l when r.l <= 0 or radius is 0.
vec3 RepresentativeDirection(vec3 r, vec3 l, float radius) {
  const float rDotL = Dot3(r, l);
  if (!(rDotL > 0.0) || !(radius > 0.0)) return l;
  precise vec3 s = r - l * rDotL;
  precise float sLength = sqrt(Dot3(s, s));
  precise float u = radius * rDotL;
  if (sLength <= u) return r;
  precise float k = (radius * u) / (sLength * (sLength + sqrt(sLength * sLength - u * u)));
  return Normalize3(l + s * k);
}

// BRDF times n.l over a disk light of angular radius atan(tanAngularRadius) around l, per unit of
// its irradiance: Lambert at the centre; GGX toward the representative direction, D limited to the
// peak of the lobe averaged over the disk. 0 when l or v is below the surface.
vec3 DiskLightBrdfCosine(vec3 albedo, float metallic, float alpha, vec3 n, vec3 v, vec3 l, float tanAngularRadius) {
  const float nDotL = Dot3(n, l);
  const float nDotV = Dot3(n, v);
  if (!(nDotL > 0.0) || !(nDotV > 0.0)) return vec3(0.0);
  precise vec3 diffuse = albedo * ((1.0 - metallic) / kPi);
  const float a = alpha < kMinGgxAlpha ? kMinGgxAlpha : alpha;
  precise float slopeRadius = (0.5 * tanAngularRadius) / sqrt(nDotV);
  precise float peakAlpha = min(1.0, sqrt(a * a + slopeRadius * slopeRadius));
  precise vec3 r = n * (2.0 * nDotV) - v;
  const vec3 toDisk = RepresentativeDirection(r, l, (tanAngularRadius * slopeRadius) / (a + peakAlpha));
  const float nDotDisk = Dot3(n, toDisk);
  precise vec3 specular = vec3(0.0);
  if (nDotDisk > 0.0) {
    precise vec3 h = v + toDisk;
    precise float hLength = sqrt(Dot3(h, h));
    h = hLength > 0.0 ? h / hLength : n;
    const float nDotH = Clamp01(Dot3(n, h));
    const float vDotH = Clamp01(Dot3(v, h));
    precise float peak = 1.0 / (kPi * (peakAlpha * peakAlpha));
    const float d = min(GgxDistribution(nDotH, a), peak);
    specular = SchlickFresnel(vDotH, SpecularF0(albedo, metallic)) *
               (d * SmithGgxCorrelatedVisibilityCosine(nDotV, nDotDisk, a));
  }
  precise vec3 result = diffuse * nDotL + specular;
  return result;
}

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;
  const int index = pixel.y * imageSize.x + pixel.x;
  const int plane = imageSize.x * imageSize.y;
  const float d = depth[index];
  precise vec3 radiance = background;
  if (d != kBackgroundDepth) {
    const vec3 ray = PixelRayDirection(vec2(pixel) + 0.5);
    precise vec3 position = vec3(0.0) + ray * d;
    const vec3 toViewer = Normalize3(-ray);
    const vec3 n = UnpackNormal(word1[index]);
    const vec3 albedo = UnpackAlbedo(word0[index]);
    const float metallic = UnpackMetallic(word0[index]);
    const float roughness = UnpackRoughness(word1[index]);
    precise float alpha = roughness * roughness;
    radiance = vec3(0.0);
    for (int i = 0; i < lightCount; ++i) {
      const Light light = lights[i];
      // core/lighting.h Evaluate: the direction to the light, its irradiance and angular radius.
      precise vec3 toLight = -light.directionRadius.xyz;
      precise vec3 irradiance = light.powerTanRadius.xyz;
      precise float tanAngularRadius = light.powerTanRadius.w;
      if (light.positionIsSpot.w != 0.0) {
        precise vec3 offset = light.positionIsSpot.xyz - position;
        precise float distance2 = Dot3(offset, offset);
        precise float distance = sqrt(distance2);
        if (distance > 0.0) toLight = offset / distance;
        precise float cone = Clamp01((Dot3(-toLight, light.directionRadius.xyz) - light.cone.x) * light.cone.y);
        const float radius = light.directionRadius.w;
        precise float radius2 = radius * radius;
        precise float falloff = cone * cone / max(distance2, max(radius2, 1e-8));
        irradiance = light.powerTanRadius.xyz * falloff;
        tanAngularRadius = distance > radius ? radius / distance : 1.0;
      }
      precise vec3 contribution =
          DiskLightBrdfCosine(albedo, metallic, alpha, n, toViewer, toLight, tanAngularRadius) * irradiance;
      if (i == shadowedLight) contribution *= visibility[index];
      radiance += contribution;
    }
  }
  direct[index] = SanitizeRadiance(radiance.r);
  direct[index + plane] = SanitizeRadiance(radiance.g);
  direct[index + 2 * plane] = SanitizeRadiance(radiance.b);
}
