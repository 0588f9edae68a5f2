// Anti-aliasing blend (docs/pipeline.md §Edge coverage and anti-aliasing, "Blend"): each pixel with
// a non-zero coverage word becomes (c w0 + left wl + right wr + up wu + down wd) / 256, each product
// and sum rounded in that order; a neighbour past the image's border is the pixel itself (its share
// is 0 there). Pixels with a zero word keep their value.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Coverage { uint coverage[]; };
layout(std430, binding = 1) readonly buffer Image { float image[]; };       // three planes
layout(std430, binding = 2) writeonly buffer Blended { float blended[]; };  // three planes

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;
  const int index = pixel.y * imageSize.x + pixel.x;
  const int plane = imageSize.x * imageSize.y;
  const uint word = coverage[index];
  if (word == 0u) {
    for (int c = 0; c < 3; ++c) blended[index + c * plane] = image[index + c * plane];
    return;
  }
  const uint l = word & 255u, r = (word >> 8) & 255u, u = (word >> 16) & 255u, d = word >> 24;
  const float wl = float(l), wr = float(r), wu = float(u), wd = float(d), w0 = float(256u - l - r - u - d);
  const int left = pixel.x > 0 ? index - 1 : index;
  const int right = pixel.x + 1 < imageSize.x ? index + 1 : index;
  const int up = pixel.y > 0 ? index - imageSize.x : index;
  const int down = pixel.y + 1 < imageSize.y ? index + imageSize.x : index;
  for (int c = 0; c < 3; ++c) {
    const int o = c * plane;
    precise float sum = image[index + o] * w0;
    sum = sum + image[left + o] * wl;
    sum = sum + image[right + o] * wr;
    sum = sum + image[up + o] * wu;
    sum = sum + image[down + o] * wd;
    blended[index + o] = sum * (1.0 / 256.0);
  }
}
