// The conventional G-buffer pass's vertices: the oracle's clip position (as visibility.vert), and
// the attributes the fragment shader interpolates: the view-space normal (mat3(view) times the
// mesh's, as the resolve rotates it) and the UV.
out vec3 viewNormal;
out vec2 uv;
out float viewDepth;

void main() {
  const uint vertex = uint(gl_VertexID);
  gl_Position = SnapToGrid(Transform(viewProjection, MeshPosition(vertex)));
  const mat3 rotation = mat3(surfaceView);
  const vec3 n = MeshNormal(vertex);
  precise vec3 rotated = rotation[0] * n.x + rotation[1] * n.y;
  precise vec3 normal = rotated + rotation[2] * n.z;
  viewNormal = normal;
  uv = uvs[vertex];
  viewDepth = -ViewPosition(vertex).z;
}
