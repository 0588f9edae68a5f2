// §G-buffer "Resolve": words 0-2 of every pixel from the visibility buffer (the triangle and its
// depth key), as GBufferResolvePixelScalar (passes/gbuffer.cpp) defines them. Background: 0, 0, +inf.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Triangles { uint visibleTriangle[]; };
layout(std430, binding = 1) readonly buffer Keys { float depthKey[]; };
layout(std430, binding = 2) writeonly buffer Word0 { uint word0[]; };
layout(std430, binding = 3) writeonly buffer Word1 { uint word1[]; };
layout(std430, binding = 4) writeonly buffer Word2 { uint word2[]; };
uniform float nearPlane;
const uint kNoTriangle = 0xFFFFFFFFu;

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;
  const uint i = uint(pixel.y * imageSize.x + pixel.x);
  const uint triangle = visibleTriangle[i];
  if (triangle == kNoTriangle) {
    word0[i] = 0u;
    word1[i] = 0u;
    word2[i] = floatBitsToUint(kBackgroundDepth);
    return;
  }
  const Material material = materials[triangleMaterial[triangle]];
  const ivec4 maps = material.textures;  // base colour, metallic, roughness, alpha
  const bool textured = maps.x >= 0 || maps.y >= 0 || maps.z >= 0;
  const SurfacePoint s = SurfaceAt(triangle, pixel, textured || specularAaKappa > 0.0);

  // The shading normal: the vertex normals blended, rotated to view space, normalised; the
  // geometric normal where the blend is zero or not finite; towards the camera on a back face.
  const uint i0 = indices[3u * triangle], i1 = indices[3u * triangle + 1u], i2 = indices[3u * triangle + 2u];
  precise vec3 blend = MeshNormal(i0) * s.weights.x + MeshNormal(i1) * s.weights.y + MeshNormal(i2) * s.weights.z;
  // Specular anti-aliasing: the blend's steps to the next pixel right and down.
  float variance = 0.0;
  if (specularAaKappa > 0.0) {
    precise vec3 edge1 = MeshNormal(i1) - MeshNormal(i0);
    precise vec3 edge2 = MeshNormal(i2) - MeshNormal(i0);
    precise vec3 stepX = edge1 * s.baryStepX.x + edge2 * s.baryStepX.y;
    precise vec3 stepY = edge1 * s.baryStepY.x + edge2 * s.baryStepY.y;
    variance = NormalVariance(blend, stepX, stepY);
  }
  const mat3 rotation = mat3(surfaceView);
  precise vec3 rotated = rotation[0] * blend.x + rotation[1] * blend.y;
  precise vec3 normal = rotated + rotation[2] * blend.z;
  const float length = sqrt(Dot3(normal, normal));
  const vec3 p0 = ViewPosition(i0);
  precise vec3 e1 = ViewPosition(i1) - p0;
  precise vec3 e2 = ViewPosition(i2) - p0;
  const vec3 faceNormal = Cross3(e1, e2);
  if (length > 0.0 && IsFinite(length)) {
    precise vec3 unit = normal / length;
    normal = unit;
  } else {
    normal = Normalize3(faceNormal);
  }
  if (Dot3(faceNormal, PixelRayDirection(vec2(pixel) + 0.5)) > 0.0) normal = -normal;

  const uvec2 words = MaterialWords(material, normal, s.uv, s.uvFootprint, variance);
  word0[i] = words.x;
  word1[i] = words.y;
  precise float depth = nearPlane / depthKey[i];
  word2[i] = floatBitsToUint(depth);
}
