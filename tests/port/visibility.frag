// The visibility pass (docs/pipeline.md §Rasterizer): for every fragment GL's rasterizer produces,
// the triangle (one draw of every triangle, so gl_PrimitiveID is the mesh's triangle index) and the
// oracle's depth key at the pixel, through gl_FragDepth into a float32 depth buffer tested GREATER
// (ties keep the earlier triangle, as GL keeps primitive order). Back faces are culled by GL's own
// facing where the material is one-sided and the pass culls, and where closedCulled says; cut-outs are alpha tested as the
// oracle tests them, at the level the spec names (texel fetches, not the hardware's sampler).
layout(location = 0) out uint triangleOut;
layout(location = 1) out float keyOut;

uniform int cullBackFaces;

void main() {
  const uint triangle = uint(gl_PrimitiveID);
  const ivec2 pixel = ivec2(gl_FragCoord.xy);
  const Material material = materials[triangleMaterial[triangle]];
  const bool cull = (cullBackFaces != 0 && material.roughnessCutoffTwoSided.z == 0.0) || closedCulled[triangle] != 0u;
  if (cull && !gl_FrontFacing) discard;
  float key;
  if (!OracleKey(triangle, pixel, key)) discard;
  if (!PassesAlphaTest(triangle, pixel)) discard;
  gl_FragDepth = key;
  triangleOut = triangle;
  keyOut = key;
}
