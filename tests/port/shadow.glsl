// What the shadow passes share (docs/pipeline.md §Shadow map and blocker search, §Receivers): the
// light-view position of a G-buffer pixel. `cameraToLight` is the light view times the camera
// view's inverse (rigid): its rotation's columns and its translation (the camera's position in the
// light view). Included after common.glsl.

uniform vec3 cameraToLight[4];

// mat3(cameraToLight) * v, glm's order.
vec3 RotateToLight(vec3 v) {
  precise vec3 r = cameraToLight[0] * v.x + cameraToLight[1] * v.y;
  precise vec3 s = r + cameraToLight[2] * v.z;
  return s;
}

// ReceiverPositions::At: the row's rays at its first and last pixel rotated into the light view,
// the pixel's direction affine between them, times the view depth, from the camera's position.
vec3 ReceiverPosition(ivec2 pixel, float depth) {
  const float py = float(pixel.y) + 0.5;
  const vec3 first = RotateToLight(PixelRayDirection(vec2(0.5, py)));
  const vec3 last = RotateToLight(PixelRayDirection(vec2(float(imageSize.x) - 0.5, py)));
  precise vec3 step = imageSize.x > 1 ? (last - first) / float(imageSize.x - 1) : vec3(0.0);
  precise vec3 p = cameraToLight[3] + (first + step * float(pixel.x)) * depth;
  return p;
}
