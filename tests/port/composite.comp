// Composite (docs/pipeline.md §Composite): indirect = the cone-traced radiance times the split-sum
// specular weight times the trace's confidence and the roughness fade, plus, with the sky light, the
// environment times the weight for the share the trace did not see, times the sky's visibility,
// plus, with the diffuse bounce, the bounce times the diffuse albedo; result = base + indirect, with
// base the lit image ("direct" below when the sky light ran), its sky diffuse light darkened by the
// bounce's visibility when both ran.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Word0 { uint word0[]; };
layout(std430, binding = 1) readonly buffer Word1 { uint word1[]; };
layout(std430, binding = 2) readonly buffer Word2 { float depth[]; };
layout(std430, binding = 3) readonly buffer Confidence { float confidence[]; };
layout(std430, binding = 4) readonly buffer Reflected { float reflected[]; };  // three planes
layout(std430, binding = 5) readonly buffer Direct { float direct[]; };        // three planes
layout(std430, binding = 6) writeonly buffer Indirect { float indirect[]; };   // three planes
layout(std430, binding = 7) writeonly buffer Result { float result[]; };       // three planes
// The split-sum DFG table (A, B) pairs at [j * 32 + i], n.v = i / 31, roughness j / 31 (core/brdf.h).
layout(std430, binding = 8) readonly buffer Dfg { vec2 dfg[]; };
layout(std430, binding = 9) readonly buffer SkyVisibility { float skyVisibility[]; };
layout(std430, binding = 10) readonly buffer DiffuseBounce { float diffuseBounce[]; };  // three planes
layout(std430, binding = 11) readonly buffer AmbientVisibility { float ambientVisibility[]; };
layout(std430, binding = 12) readonly buffer SkyDiffuse { float skyDiffuse[]; };  // three planes
// The sky light's interreflection volume towards the mirror direction, where it has one.
layout(std430, binding = 13) readonly buffer SkyReflected { float skyReflected[]; };  // three planes

uniform float roughnessCutoff;  // the trace's
uniform int hasSkyReflected;    // 1: skyReflected is bound
uniform int reflections;        // 0: no reflections traced (confidence 0 everywhere)
uniform int sky;                // 1: the sky light ran: its specular part here
uniform int bounceRan;          // 1: the diffuse bounce ran: its light here, and its occlusion of the sky's
uniform int constantEnvironment;  // 1: the environment is `skyRadiance`; else its levels (common.glsl)
uniform vec3 skyRadiance;

const int kDfgSize = 32;

vec2 DfgEntry(int i, int j) { return dfg[j * kDfgSize + i]; }

vec3 SpecularWeight(vec3 f0, float nDotV, float roughness) {
  precise float u = clamp(nDotV, 0.0, 1.0) * float(kDfgSize - 1);
  precise float v = clamp(roughness, 0.0, 1.0) * float(kDfgSize - 1);
  const int i0 = min(int(u), kDfgSize - 2);
  const int j0 = min(int(v), kDfgSize - 2);
  precise float fu = u - float(i0);
  precise float fv = v - float(j0);
  precise vec2 top = DfgEntry(i0, j0) + (DfgEntry(i0 + 1, j0) - DfgEntry(i0, j0)) * fu;
  precise vec2 bottom = DfgEntry(i0, j0 + 1) + (DfgEntry(i0 + 1, j0 + 1) - DfgEntry(i0, j0 + 1)) * fu;
  precise vec2 ab = top + (bottom - top) * fv;
  precise vec3 weight = f0 * ab.x + vec3(ab.y);
  return weight;
}

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;
  const int index = pixel.y * imageSize.x + pixel.x;
  const int plane = imageSize.x * imageSize.y;
  precise vec3 indirectRadiance = vec3(0.0);
  const float trust = reflections != 0 ? confidence[index] : 0.0;
  precise vec3 base = vec3(direct[index], direct[index + plane], direct[index + 2 * plane]);
  if (depth[index] != kBackgroundDepth && (trust > 0.0 || sky != 0 || bounceRan != 0)) {
    const uint w0 = word0[index];
    const uint w1 = word1[index];
    const float roughness = UnpackRoughness(w1);
    const vec3 albedo = UnpackAlbedo(w0);
    const float metallic = UnpackMetallic(w0);
    if (trust > 0.0 || sky != 0) {
      const vec3 f0 = SpecularF0(albedo, metallic);
      const vec3 toViewer = Normalize3(-PixelRayDirection(vec2(pixel) + 0.5));
      precise float nDotV = clamp(Dot3(UnpackNormal(w1), toViewer), 0.0, 1.0);
      precise float fade = clamp((roughnessCutoff - roughness) / 0.1, 0.0, 1.0);
      precise vec3 specular = SpecularWeight(f0, nDotV, roughness);
      if (trust > 0.0) {
        const vec3 traced = vec3(reflected[index], reflected[index + plane], reflected[index + 2 * plane]);
        // The weight first, then the radiance times it (§Composite).
        precise vec3 weight = specular * (trust * fade);
        indirectRadiance = traced * weight;
      }
      if (sky != 0) {
        precise float unseen = 1.0 - trust * fade;
        precise float share = unseen * skyVisibility[index];
        // Towards the mirror direction r = 2 (n.v) n - v, in world space.
        const vec3 normal = UnpackNormal(w1);
        precise vec3 reflection = normal * (2.0 * Dot3(normal, toViewer)) - toViewer;
        const vec3 radiance =
            constantEnvironment != 0 ? skyRadiance : PrefilteredEnvironment(Rotate(reflection), roughness);
        precise vec3 environment = radiance * (specular * share);
        indirectRadiance = indirectRadiance + environment;
        if (hasSkyReflected != 0) {
          // The surfaces around, which the sky's visibility took away from the environment's light.
          const vec3 around = vec3(skyReflected[index], skyReflected[index + plane], skyReflected[index + 2 * plane]);
          precise vec3 surroundings = around * (specular * unseen);
          indirectRadiance = indirectRadiance + surroundings;
        }
      }
    }
    if (bounceRan != 0) {
      // A Lambertian surface reflects its diffuse albedo times E / pi (the bounce), after the terms above.
      precise vec3 diffuseAlbedo = albedo * (1.0 - metallic);
      const vec3 arriving = vec3(diffuseBounce[index], diffuseBounce[index + plane], diffuseBounce[index + 2 * plane]);
      precise vec3 reflectedBounce = arriving * diffuseAlbedo;
      indirectRadiance = indirectRadiance + reflectedBounce;
      // The lit image holds the sky's diffuse light unoccluded by the surfaces around the pixel: the
      // share 1 - visibility of it is taken away, `visibility - 1` rounded first.
      if (sky != 0) {
        precise float darkening = ambientVisibility[index] - 1.0;
        const vec3 skyLight = vec3(skyDiffuse[index], skyDiffuse[index + plane], skyDiffuse[index + 2 * plane]);
        precise vec3 occluded = skyLight * darkening;
        base = base + occluded;
      }
    }
  }
  precise vec3 sum = base + indirectRadiance;
  for (int c = 0; c < 3; ++c) {
    indirect[index + c * plane] = indirectRadiance[c];
    result[index + c * plane] = sum[c];
  }
}
