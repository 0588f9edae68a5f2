// §Sky light, the sky visibility volume: one dispatch per direction, in the directions' order, over
// every cell centre (x, y a dispatch's plane, z its depth). A centre sees the sky along w_i unless
// its texel of map i holds a surface nearer the sky than it by more than half a cell; then
// k0 += 1/N and (kx, ky, kz) += 2 w_i / N, each sum in the oracle's order (CellsSeeingSky and
// BuildSkyVisibility in passes/sky_light.cpp are the definition).
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Map { float depthKey[]; };  // size^2, rows from the top
layout(std430, binding = 1) buffer Volume { float coefficients[]; };    // 4 per cell

uniform ivec3 cells;
uniform vec3 origin;
uniform float cellSize;
uniform mat4 mapView;  // world -> the map's view (glm's matrix)
uniform vec2 mapHalf;  // the map's halfX, halfY
uniform int mapSize;
uniform float mapNear, mapFar;
uniform float share;            // 1/N
uniform vec3 towardSky;         // w_i

// glm's mat4 * vec4 with w = 1: (m0 x + m1 y) + (m2 z + m3), each product rounded.
vec4 TransformPoint(mat4 m, vec3 p) {
  precise vec4 xy = m[0] * p.x + m[1] * p.y;
  precise vec4 zw = m[2] * p.z + m[3];
  precise vec4 sum = xy + zw;
  return sum;
}

bool SeesSky(ivec3 c) {
  precise vec3 p = origin + (vec3(c) + 0.5) * cellSize;
  const vec4 v = TransformPoint(mapView, p);
  const float size = float(mapSize);
  precise float px = (v.x / mapHalf.x + 1.0) * 0.5 * size;
  precise float py = (1.0 - v.y / mapHalf.y) * 0.5 * size;
  if (!(px >= 0.0 && px < size && py >= 0.0 && py < size)) return true;
  const float key = depthKey[int(py) * mapSize + int(px)];
  precise float bias = 0.5 * cellSize;
  precise float depth = mapNear + (1.0 - key) * (mapFar - mapNear);
  precise float nearer = depth + bias;
  return !(key > 0.0 && nearer < -v.z);
}

void main() {
  const ivec3 c = ivec3(gl_GlobalInvocationID);
  if (c.x >= cells.x || c.y >= cells.y || c.z >= cells.z) return;
  if (!SeesSky(c)) return;
  const int at = ((c.z * cells.y + c.y) * cells.x + c.x) * 4;
  precise float twoShare = 2.0 * share;
  precise float k0 = coefficients[at] + share;
  precise float kx = coefficients[at + 1] + twoShare * towardSky.x;
  precise float ky = coefficients[at + 2] + twoShare * towardSky.y;
  precise float kz = coefficients[at + 3] + twoShare * towardSky.z;
  coefficients[at] = k0;
  coefficients[at + 1] = kx;
  coefficients[at + 2] = ky;
  coefficients[at + 3] = kz;
}
