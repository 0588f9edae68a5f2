// §Light camera: the receivers (every G-buffer pixel with geometry) in the light's view, as
// (x, y, depth = -z), each component + 0 (so -0 counts as +0): their count and bounds, per group of
// 8x8 pixels. The runner folds the groups: minima and maxima of values without NaN or -0 do not
// depend on the order they are taken in.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Word2 { uint word2[]; };
// Per group: count, then lo.xyz, hi.xyz.
layout(std430, binding = 1) writeonly buffer Partials { float partials[]; };

shared vec3 groupLo[64];
shared vec3 groupHi[64];
shared uint groupCount[64];

// glm's min(a, b) = b < a ? b : a and max(a, b) = a < b ? b : a, per component.
vec3 GlmMin(vec3 a, vec3 b) { return vec3(b.x < a.x ? b.x : a.x, b.y < a.y ? b.y : a.y, b.z < a.z ? b.z : a.z); }
vec3 GlmMax(vec3 a, vec3 b) { return vec3(a.x < b.x ? b.x : a.x, a.y < b.y ? b.y : a.y, a.z < b.z ? b.z : a.z); }

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  const uint local = gl_LocalInvocationIndex;
  groupLo[local] = vec3(uintBitsToFloat(0x7F800000u));
  groupHi[local] = vec3(-uintBitsToFloat(0x7F800000u));
  groupCount[local] = 0u;
  if (pixel.x < imageSize.x && pixel.y < imageSize.y) {
    const float depth = uintBitsToFloat(word2[pixel.y * imageSize.x + pixel.x]);
    if (depth < kBackgroundDepth) {
      const vec3 p = ReceiverPosition(pixel, depth);
      precise vec3 q = vec3(p.x + 0.0, p.y + 0.0, -p.z + 0.0);
      groupLo[local] = q;
      groupHi[local] = q;
      groupCount[local] = 1u;
    }
  }
  barrier();
  for (uint stride = 32u; stride > 0u; stride /= 2u) {
    if (local < stride) {
      groupLo[local] = GlmMin(groupLo[local], groupLo[local + stride]);
      groupHi[local] = GlmMax(groupHi[local], groupHi[local + stride]);
      groupCount[local] += groupCount[local + stride];
    }
    barrier();
  }
  if (local == 0u) {
    const uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    partials[7u * group] = float(groupCount[0]);
    for (int c = 0; c < 3; ++c) {
      partials[7u * group + 1u + uint(c)] = groupLo[0][c];
      partials[7u * group + 4u + uint(c)] = groupHi[0][c];
    }
  }
}
