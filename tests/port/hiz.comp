// Hi-Z pyramid (docs/pipeline.md §Hi-Z pyramid), one dispatch per level. Level 0 is the inverse
// view depth 1/d of G-buffer word 2 (background +inf gives exactly 0); level k+1 is the max of its
// footprint in level k. Every value is a max of exactly computed values: bit-exact with the oracle.
layout(local_size_x = 8, local_size_y = 8) in;

// Level 0: word 2's bits (a float); otherwise level k.
layout(std430, binding = 0) readonly buffer Source { float source[]; };
layout(std430, binding = 1) writeonly buffer Destination { float destination[]; };
uniform ivec2 sourceSize;
uniform ivec2 destinationSize;
uniform bool invertDepth;  // level 0: destination = 1 / source, same size

void main() {
  const ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (texel.x >= destinationSize.x || texel.y >= destinationSize.y) return;
  const int index = texel.y * destinationSize.x + texel.x;
  if (invertDepth) {
    precise float inverseDepth = 1.0 / source[index];
    destination[index] = inverseDepth;
    return;
  }
  const int lastX = FootprintEnd(texel.x, destinationSize.x, sourceSize.x);
  const int lastY = FootprintEnd(texel.y, destinationSize.y, sourceSize.y);
  // From 0, row by row, left column first; `v` replaces `closest` only where closest < v, so a NaN
  // never reaches a coarser level (the oracle's std::max(closest, v)).
  float closest = 0.0;
  for (int y = 2 * texel.y; y <= lastY; ++y) {
    for (int x = 2 * texel.x; x <= lastX; ++x) {
      const float v = source[y * sourceSize.x + x];
      closest = closest < v ? v : closest;
    }
  }
  destination[index] = closest;
}
