// glTF scenes through the G-buffer and the direct light: a metallic-roughness sphere grid in the
// style of Khronos's MetalRoughSpheres, written here and loaded back, against the BRDF; the same
// model as OBJ+MTL and as glTF giving the same G-buffer.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "core/brdf.h"
#include "core/gltf_loader.h"
#include "core/image_io.h"
#include "core/scene.h"
#include "passes/direct_light.h"
#include "passes/gbuffer.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// A .gltf with one buffer (beside it, base64-free) from float positions, normals, UVs and indices.
struct GltfMesh {
  std::vector<float> positions, normals, uvs;
  std::vector<uint32_t> indices;
};

// Appends `mesh` as buffer views and accessors of `json` (whose buffer 0 is `bin`); returns its
// primitive (without material).
Json AddPrimitive(Json& json, std::vector<uint8_t>& bin, const GltfMesh& mesh) {
  const auto view = [&](const void* data, size_t bytes) {
    const size_t offset = bin.size();
    bin.insert(bin.end(), static_cast<const uint8_t*>(data), static_cast<const uint8_t*>(data) + bytes);
    json["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
    return json["bufferViews"].size() - 1;
  };
  const auto accessor = [&](const auto& values, int componentType, const char* type, size_t count) {
    Json a = {{"bufferView", view(values.data(), values.size() * 4)},
              {"componentType", componentType},
              {"type", type},
              {"count", count}};
    json["accessors"].push_back(a);
    return json["accessors"].size() - 1;
  };
  const size_t vertices = mesh.positions.size() / 3;
  Json attributes = {{"POSITION", accessor(mesh.positions, 5126, "VEC3", vertices)},
                     {"NORMAL", accessor(mesh.normals, 5126, "VEC3", vertices)}};
  if (!mesh.uvs.empty()) attributes["TEXCOORD_0"] = accessor(mesh.uvs, 5126, "VEC2", vertices);
  return {{"attributes", attributes}, {"indices", accessor(mesh.indices, 5125, "SCALAR", mesh.indices.size())}};
}

void WriteGltf(const fs::path& file, Json json, const std::vector<uint8_t>& bin) {
  const fs::path binFile = file.parent_path() / (file.stem().string() + ".bin");
  json["asset"] = {{"version", "2.0"}};
  json["buffers"] = {{{"uri", binFile.filename().string()}, {"byteLength", bin.size()}}};
  std::ofstream(binFile, std::ios::binary)
      .write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));
  test::WriteText(file, json.dump());
}

GltfMesh UvSphere(float radius, int rings, int segments) {
  GltfMesh m;
  const double pi = 3.14159265358979323846;
  for (int r = 0; r <= rings; ++r) {
    for (int s = 0; s <= segments; ++s) {
      const double theta = pi * r / rings, phi = 2.0 * pi * s / segments;
      const glm::dvec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
      for (int k = 0; k < 3; ++k) {
        m.positions.push_back(float(n[k] * radius));
        m.normals.push_back(float(n[k]));
      }
      m.uvs.push_back(float(s) / float(segments));
      m.uvs.push_back(float(r) / float(rings));
    }
  }
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      const uint32_t a = uint32_t(r * (segments + 1) + s), b = a + uint32_t(segments + 1);
      m.indices.insert(m.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  }
  return m;
}

// Direct radiance of a zero-size sun, as tests/passes/direct_light_test.cpp's AnalyticRadiance
// (GGX, height-correlated Smith, Schlick; Filament's formulation), in double.
glm::dvec3 Analytic(glm::dvec3 albedo, double metallic, double roughness, glm::dvec3 n, glm::dvec3 v, glm::dvec3 l,
                    glm::dvec3 irradiance) {
  const double pi = 3.14159265358979323846;
  const double nl = glm::dot(n, l), nv = glm::dot(n, v);
  if (nl <= 0.0 || nv <= 0.0) return glm::dvec3(0.0);
  const glm::dvec3 h = glm::normalize(v + l);
  const double nh = glm::dot(n, h), vh = glm::dot(v, h);
  const double alpha = std::max(roughness * roughness, double(kMinGgxAlpha));
  const double a2 = alpha * alpha;
  const double d = a2 / (pi * std::pow(nh * nh * (a2 - 1.0) + 1.0, 2.0));
  const double vis = 0.5 / (nl * std::sqrt(nv * nv * (1.0 - a2) + a2) + nv * std::sqrt(nl * nl * (1.0 - a2) + a2));
  const glm::dvec3 f0 = glm::mix(glm::dvec3(0.04), albedo, metallic);
  const glm::dvec3 f = f0 + (glm::dvec3(1.0) - f0) * std::pow(1.0 - vh, 5.0);
  return (albedo * (1.0 - metallic) / pi + d * vis * f) * nl * irradiance;
}

TEST_CASE("glTF: a metallic-roughness sphere grid renders as the BRDF says: roughness to the right, metal upwards",
          "[gltf]") {
  // Five by five spheres 2.5 m apart facing a camera 24 m away; the sun comes from behind the camera's
  // left shoulder. Column c has roughness c / 4, row r (counted upwards) metallic r / 4.
  test::ScratchDir dir("gltf-spheres");
  Json json;
  std::vector<uint8_t> bin;
  const Json sphere = AddPrimitive(json, bin, UvSphere(1.0f, 48, 96));
  json["meshes"] = Json::array();
  json["scene"] = 0;
  json["scenes"] = {{{"nodes", Json::array()}}};
  for (int row = 0; row < 5; ++row) {
    for (int column = 0; column < 5; ++column) {
      json["materials"].push_back({{"pbrMetallicRoughness",
                                    {{"baseColorFactor", {0.9, 0.6, 0.3, 1.0}},
                                     {"metallicFactor", row / 4.0},
                                     {"roughnessFactor", column / 4.0}}}});
      Json primitive = sphere;
      primitive["material"] = json["materials"].size() - 1;
      json["meshes"].push_back({{"primitives", {primitive}}});
      json["nodes"].push_back(
          {{"mesh", json["meshes"].size() - 1}, {"translation", {2.5 * (column - 2), 2.5 * (row - 2), 0}}});
      json["scenes"][0]["nodes"].push_back(json["nodes"].size() - 1);
    }
  }
  json["cameras"] = {
      {{"type", "perspective"}, {"perspective", {{"yfov", 0.55}, {"znear", 1.0}, {"aspectRatio", 1.0}}}}};
  json["nodes"].push_back({{"camera", 0}, {"translation", {0, 0, 24}}});
  json["scenes"][0]["nodes"].push_back(json["nodes"].size() - 1);
  json["extensionsUsed"] = {"KHR_lights_punctual"};
  json["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "directional"}, {"intensity", 683.0 * 3.0}}};
  // -z turned towards (-0.3, -0.4, -1): the light travels into the scene from the upper left.
  const glm::dvec3 bz = -glm::normalize(glm::dvec3(0.3, -0.4, -1.0));
  const glm::dvec3 bx = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), bz)), by = glm::cross(bz, bx);
  json["nodes"].push_back({{"matrix", {bx.x, bx.y, bx.z, 0, by.x, by.y, by.z, 0, bz.x, bz.y, bz.z, 0, 0, 0, 0, 1}},
                           {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  json["scenes"][0]["nodes"].push_back(json["nodes"].size() - 1);
  WriteGltf(dir / "spheres.gltf", json, bin);

  Scene scene = LoadScene(dir / "spheres.gltf");
  REQUIRE(scene.directionalLights.size() == 1);
  CHECK(scene.directionalLights[0].irradiance.x == Approx(3.0f));
  scene.directionalLights[0].castShadows = false;
  constexpr int kSide = 400;
  const ViewProjection view = MakePerspective(scene.camera, kSide, kSide);
  GBufferOutputs g;
  RunGBuffer({scene, view}, {}, g);
  DirectLightOutputs direct;
  RunDirectLight({g.gbuffer, view, scene}, {}, direct);

  const glm::dmat4 toView(view.view);
  const glm::dvec3 l = glm::normalize(glm::dmat3(toView) * -glm::dvec3(scene.directionalLights[0].direction));
  std::vector<double> centre(25), peak(25, 0.0);
  for (int row = 0; row < 5; ++row) {
    for (int column = 0; column < 5; ++column) {
      // The pixel of the sphere's centre, and one a third of a radius towards the upper left.
      const glm::vec4 clip =
          view.viewProjection * glm::vec4(2.5f * float(column - 2), 2.5f * float(row - 2), 0.0f, 1.0f);
      const int cx = int((clip.x / clip.w * 0.5f + 0.5f) * kSide), cy = int((0.5f - clip.y / clip.w * 0.5f) * kSide);
      for (const glm::ivec2 offset : {glm::ivec2(0, 0), glm::ivec2(-5, -5)}) {
        const int x = cx + offset.x, y = cy + offset.y;
        CAPTURE(row, column, x, y);
        const uint32_t w0 = g.gbuffer.word[0].ConstRow(size_t(y))[x], w1 = g.gbuffer.word[1].ConstRow(size_t(y))[x];
        // The G-buffer holds the grid's materials: metal upwards, roughness to the right.
        CHECK(UnpackMetallic(w0) == Approx(row / 4.0).margin(0.6 / 255));
        CHECK(UnpackRoughness(w1) == Approx(column / 4.0).margin(0.6 / 255));
        const glm::dvec3 v = glm::normalize(-glm::dvec3(view.PixelRay(float(x) + 0.5f, float(y) + 0.5f).direction));
        const glm::dvec3 expected =
            Analytic(glm::dvec3(UnpackAlbedo(w0)), UnpackMetallic(w0), UnpackRoughness(w1),
                     glm::dvec3(UnpackNormal(w1, g.gbuffer.normalEncoding)), v, l, glm::dvec3(3.0));
        const glm::vec3 got(direct.radiance.c[0].ConstRow(size_t(y))[x], direct.radiance.c[1].ConstRow(size_t(y))[x],
                            direct.radiance.c[2].ConstRow(size_t(y))[x]);
        for (int c = 0; c < 3; ++c) CHECK(double(got[c]) == Approx(expected[c]).epsilon(2e-3).margin(1e-6));
        if (offset == glm::ivec2(0, 0)) centre[size_t(5 * row + column)] = double(got.x + got.y + got.z);
      }
      // The sphere's disk on screen is about 16 pixels in radius: its brightest pixel within 14.
      for (int y = cy - 14; y <= cy + 14; ++y)
        for (int x = cx - 14; x <= cx + 14; ++x)
          if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= 14 * 14)
            peak[size_t(5 * row + column)] =
                std::max(peak[size_t(5 * row + column)], double(direct.radiance.c[0].ConstRow(size_t(y))[x] +
                                                                direct.radiance.c[1].ConstRow(size_t(y))[x] +
                                                                direct.radiance.c[2].ConstRow(size_t(y))[x]));
    }
  }
  // The BRDF's trends: in every row the highlight's peak (the brightest pixel of the sphere) falls as
  // the roughness rises (from 0.25: the mirror's highlight of a point-sized sun is narrower than a
  // pixel); in the roughest column the dielectric's diffuse light at the centre fades as the metal
  // rises.
  for (int row = 0; row < 5; ++row) {
    for (int column = 2; column < 5; ++column) {
      CAPTURE(row, column);
      CHECK(peak[size_t(5 * row + column)] < peak[size_t(5 * row + column - 1)]);
    }
  }
  for (int row = 1; row < 5; ++row) CHECK(centre[size_t(5 * row + 4)] < centre[size_t(5 * (row - 1) + 4)]);
}

TEST_CASE("glTF: the same model as OBJ+MTL and as glTF gives the same G-buffer", "[gltf]") {
  // A textured box of 12 triangles with per-face normals, the same material (Kd/baseColorFactor,
  // Pm/metallicFactor, Pr/roughnessFactor, map_Kd/baseColorTexture) in both files, the same camera.
  test::ScratchDir dir("gltf-obj");
  std::mt19937 rng(3);
  std::vector<uint8_t> rgb(16 * 16 * 3);
  for (uint8_t& t : rgb) t = uint8_t(rng());
  WritePng(dir / "tex.png", 16, 16, rgb);
  Mesh box;
  AddBox(box, glm::vec3(-1.0f, -0.5f, -0.8f), glm::vec3(1.0f, 0.7f, 0.6f));
  std::string obj = "mtllib box.mtl\nusemtl m\n";
  GltfMesh gltf;
  for (size_t v = 0; v < box.positions.size(); ++v) {
    const glm::vec3 p = box.positions[v], n = box.normals[v];
    const glm::vec2 uv(0.3f * p.x + 0.2f * p.z, 0.4f * p.y - 0.1f * p.z);
    box.uvs[v] = uv;
    obj += "v " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
    obj += "vn " + std::to_string(n.x) + " " + std::to_string(n.y) + " " + std::to_string(n.z) + "\n";
    obj += "vt " + std::to_string(uv.x) + " " + std::to_string(uv.y) + "\n";
  }
  for (size_t t = 0; t < box.TriangleCount(); ++t) {
    obj += "f";
    for (int k = 0; k < 3; ++k) {
      const std::string i = std::to_string(box.indices[3 * t + size_t(k)] + 1);
      obj += " " + i + "/" + i + "/" + i;
    }
    obj += "\n";
  }
  test::WriteText(dir / "box.obj", obj);
  test::WriteText(dir / "box.mtl", "newmtl m\nKd 0.9 0.7 0.5\nPm 0.3\nPr 0.6\nmap_Kd tex.png\n");
  // glTF from the values the OBJ holds (as the OBJ loader reads its text) and its v turned down.
  const Scene fromObj = [&] {
    test::WriteText(dir / "obj.json", R"({"camera": {"position": [2.5, 1.8, 3.2], "target": [0, 0, 0]},
        "objects": [{"obj": "box.obj"}]})");
    return LoadScene(dir / "obj.json");
  }();
  for (size_t v = 0; v < fromObj.mesh.positions.size(); ++v) {
    for (int k = 0; k < 3; ++k) {
      gltf.positions.push_back(fromObj.mesh.positions[v][k]);
      gltf.normals.push_back(fromObj.mesh.normals[v][k]);
    }
    gltf.uvs.push_back(fromObj.mesh.uvs[v].x);
    gltf.uvs.push_back(1.0f - fromObj.mesh.uvs[v].y);
  }
  gltf.indices = fromObj.mesh.indices;
  Json json;
  std::vector<uint8_t> bin;
  Json primitive = AddPrimitive(json, bin, gltf);
  primitive["material"] = 0;
  json["meshes"] = {{{"primitives", {primitive}}}};
  json["nodes"] = {{{"mesh", 0}}};
  json["scenes"] = {{{"nodes", {0}}}};
  json["images"] = {{{"uri", "tex.png"}}};
  json["textures"] = {{{"source", 0}}};
  json["materials"] = {{{"name", "m"},
                        {"pbrMetallicRoughness",
                         {{"baseColorFactor", {0.9, 0.7, 0.5, 1.0}},
                          {"metallicFactor", 0.3},
                          {"roughnessFactor", 0.6},
                          {"baseColorTexture", {{"index", 0}}}}}}};
  WriteGltf(dir / "box.gltf", json, bin);
  test::WriteText(dir / "gltf.json", R"({"camera": {"position": [2.5, 1.8, 3.2], "target": [0, 0, 0]},
      "objects": [{"gltf": "box.gltf"}]})");
  const Scene fromGltf = LoadScene(dir / "gltf.json");
  REQUIRE(fromGltf.mesh.TriangleCount() == fromObj.mesh.TriangleCount());

  for (const glm::ivec2 size : {glm::ivec2(160, 120), glm::ivec2(67, 45)}) {
    const ViewProjection view = MakePerspective(fromObj.camera, size.x, size.y);
    GBufferOutputs a, b;
    RunGBuffer({fromObj, view}, {}, a);
    RunGBuffer({fromGltf, view}, {}, b);
    size_t covered = 0;
    for (size_t y = 0; y < size_t(size.y); ++y)
      for (size_t x = 0; x < size_t(size.x); ++x) covered += a.visibility.triangle.ConstRow(y)[x] != kNoTriangle;
    CHECK(covered > size_t(size.x * size.y) / 8);
    for (int w = 0; w < 4; ++w) CHECK(test::SameBytes(a.gbuffer.word[w], b.gbuffer.word[w]));
  }
}

}  // namespace
}  // namespace ssgi
