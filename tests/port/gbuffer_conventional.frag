// The conventional G-buffer pass: the four packed words straight from GL's interpolation
// (RGBA32UI), as a GPU port without a visibility buffer writes them, to measure how far that moves
// them from the oracle's resolve (tests/port/README.md). GL's own depth test on its own depth
// (gl_FragCoord.z, tested GREATER); the view depth, the normal and the UV perspective-correct
// varyings (1 / gl_FragCoord.w and near / gl_FragCoord.z measured no closer to the oracle's depth);
// textures at the level the spec's formula gives for the UV footprint max(|dUV/dx|, |dUV/dy|) of
// GL's fine derivatives, read with texel fetches (surface.glsl's sampler), not the hardware's level
// of detail; the cut-out test the visibility pass's; word 3 lit (the shadow pass writes it). The
// triangle index goes to a second target, for `ssgi diff`'s coverage classification.
in vec3 viewNormal;
in vec2 uv;
in float viewDepth;
layout(location = 0) out uvec4 words;
layout(location = 1) out uint triangleOut;

uniform int cullBackFaces;

void main() {
  const uint triangle = uint(gl_PrimitiveID);
  const ivec2 pixel = ivec2(gl_FragCoord.xy);
  const Material material = materials[triangleMaterial[triangle]];
  if (cullBackFaces != 0 && material.roughnessCutoffTwoSided.z == 0.0 && !gl_FrontFacing) discard;
  // The cut-out test is the visibility pass's: the same surface point and level, so both forms cut
  // the same holes.
  const float footprint = max(Length2(dFdxFine(uv)), Length2(dFdyFine(uv)));
  if (!PassesAlphaTest(triangle, pixel)) discard;
  const float length = sqrt(Dot3(viewNormal, viewNormal));
  precise vec3 normal = viewNormal / length;
  // A two-sided surface seen from behind shades with the side that faces the camera.
  if (!gl_FrontFacing) normal = -normal;
  // Specular anti-aliasing from the interpolated normal's fine derivatives (its steps within the
  // quad) in place of the steps to the rays of the next pixels.
  const float variance =
      specularAaKappa > 0.0 ? NormalVariance(viewNormal, dFdxFine(viewNormal), dFdyFine(viewNormal)) : 0.0;
  const uvec2 material01 = MaterialWords(material, normal, uv, footprint, variance);
  precise float depth = viewDepth;
  words = uvec4(material01, floatBitsToUint(depth), 0u);
  triangleOut = triangle;
}
