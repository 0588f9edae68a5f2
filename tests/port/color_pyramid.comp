// Colour pyramid (docs/pipeline.md §Colour pyramid). Buffers hold the three channels as three
// planes of width x height floats, one invocation per texel and channel (z). One stage per dispatch:
// level 0 is the sanitised direct light; level k+1 is level k blurred horizontally, then
// vertically, then averaged over each texel's footprint weighted by level-0 area.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Source { float source[]; };
layout(std430, binding = 1) writeonly buffer Destination { float destination[]; };

const int kSanitize = 0;    // direct light -> level 0, same size
const int kHorizontal = 1;  // level k -> its horizontal blur, same size
const int kVertical = 2;    // horizontal blur -> vertical blur, same size
const int kDownsample = 3;  // blurred level k -> level k + 1
uniform int stage;
uniform ivec2 sourceSize;
uniform ivec2 destinationSize;
// kColorPyramidWeights: 0.001, 0.028, 0.233, 0.474, 0.233, 0.028, 0.001, each divided by 0.998 in
// double and rounded to float32 (by the runner).
uniform float weights[7];
// kDownsample: the source level's index, so that a source texel's level-0 area can be computed;
// level0Size is the image size.
uniform int sourceLevel;
uniform ivec2 level0Size;


// How many level-0 texels texel `x` of level `level` covers along an axis whose level-0 size is
// `size0`: 2^level, except the level's last texel, which runs to the border (§Hi-Z pyramid).
int Level0Span(int x, int levelSize, int level, int size0) {
  return x + 1 == levelSize ? size0 - (x << level) : 1 << level;
}

float Blur(int planeOffset, ivec2 texel, ivec2 step) {
  precise float sum = 0.0;
  for (int tap = 0; tap < 7; ++tap) {
    const ivec2 at = clamp(texel + (tap - 3) * step, ivec2(0), sourceSize - 1);
    sum += weights[tap] * source[planeOffset + at.y * sourceSize.x + at.x];
  }
  return sum;
}

void main() {
  const ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  const int channel = int(gl_GlobalInvocationID.z);
  if (texel.x >= destinationSize.x || texel.y >= destinationSize.y) return;
  const int sourceOffset = channel * sourceSize.x * sourceSize.y;
  const int index = channel * destinationSize.x * destinationSize.y + texel.y * destinationSize.x + texel.x;
  if (stage == kSanitize) {
    destination[index] = SanitizeRadiance(source[index]);
  } else if (stage == kHorizontal) {
    destination[index] = Blur(sourceOffset, texel, ivec2(1, 0));
  } else if (stage == kVertical) {
    destination[index] = Blur(sourceOffset, texel, ivec2(0, 1));
  } else {
    const int lastX = FootprintEnd(texel.x, destinationSize.x, sourceSize.x);
    const int lastY = FootprintEnd(texel.y, destinationSize.y, sourceSize.y);
    precise float sum = 0.0;
    precise float area = 0.0;
    for (int y = 2 * texel.y; y <= lastY; ++y) {
      const int rows = Level0Span(y, sourceSize.y, sourceLevel, level0Size.y);
      for (int x = 2 * texel.x; x <= lastX; ++x) {
        const float weight = float(rows * Level0Span(x, sourceSize.x, sourceLevel, level0Size.x));
        sum += source[sourceOffset + y * sourceSize.x + x] * weight;
        area += weight;
      }
    }
    precise float mean = sum / area;
    destination[index] = mean;
  }
}
