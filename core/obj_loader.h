// Wavefront OBJ + MTL loading, internal to core (the scene loader bakes its result into world space).
//
// tinyobjloader parses; this layer adds the checks it leaves out and names the file and line of each
// problem: non-finite or non-numeric `v`/`vn`/`vt` values (tinyobjloader reads "nan" and "inf" as 0),
// face indices out of range (it only warns, and drops quads that use them), missing MTL files (it
// only warns) and missing textures.
//
// Geometry: polygons are triangulated; each distinct (position, uv, normal) corner becomes one
// vertex. Corners without a usable normal get a generated one: the area-weighted normals of the
// faces at that position whose normal is within kCreaseAngleDegrees of the corner's own face, so
// hard edges stay hard and scans stay smooth. Smoothing groups (`s`) are ignored. Zero-area
// triangles are kept (the rasterizer drops them) and get a finite normal. Inconsistent winding is
// repaired first: across each edge two triangles share, the one wound against the larger part of
// its connected surface is turned (OrientConsistently in obj_loader.cpp).
//
// Materials (docs/user-guide.md "Scene files"): Kd -> baseColor (linear, as written), Pm -> metallic,
// Pr -> roughness. A value the MTL leaves out is 1 when its texture is given, so the texture is used
// as is; otherwise baseColor 0.8, metallic 0, and roughness from the Phong exponent Ns
// (alpha = sqrt(2 / (Ns + 2)), r = sqrt(alpha)) or 0.5 without Ns. Faces without a material get
// kDefaultMaterialName (baseColor 0.8, roughness 0.5).
#pragma once

#include <filesystem>
#include <vector>

#include "core/material.h"
#include "core/mesh.h"

namespace ssgi {

inline constexpr float kCreaseAngleDegrees = 60.0f;
inline constexpr const char* kDefaultMaterialName = "(default)";

// A material with the image files of its textures (empty path: none), resolved relative to the MTL
// file, letter case ignored when the exact name is missing. The texture indices in `material` are
// kNoTexture: the scene assigns them when it loads the images.
struct ObjMaterial {
  Material material;
  std::filesystem::path baseColorTexture;  // map_Kd, sRGB
  std::filesystem::path metallicTexture;   // map_Pm, linear
  std::filesystem::path roughnessTexture;  // map_Pr, linear
  std::filesystem::path alphaTexture;      // map_d, linear
};

struct ObjModel {
  Mesh mesh;                           // object space; mesh.materials index `materials`; at least one triangle
  std::vector<ObjMaterial> materials;  // in MTL order, then kDefaultMaterialName if a face has none
  size_t reorientedTriangles = 0;      // triangles whose winding was turned to match their neighbours
};

// Loads `file` and the MTL files it names with mtllib (relative to it, letter case ignored when the
// exact name is missing, as for textures). Throws InputError naming the file and line for malformed
// or non-finite data, out-of-range indices, a missing OBJ, MTL or texture, and an OBJ without faces.
ObjModel LoadObjModel(const std::filesystem::path& file);

}  // namespace ssgi
