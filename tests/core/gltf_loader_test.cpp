// glTF 2.0 loading (core/gltf_loader.h) on files written here: every accessor component type
// (normalized and KHR_mesh_quantization's), strips and fans, the node hierarchy, materials and their
// textures' channels, alpha modes, KHR_texture_transform, lights with their units, cameras, tangent
// generation; bad input refused with one line (a table and a mutation fuzz, as the OBJ loader's);
// and the files Debian's assimp-testmodels ship, each rendered or refused as docs/user-guide.md
// lists.
#include "core/gltf_loader.h"

#include <OpenImageIO/imageio.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/gbuffer.h"
#include "core/scene.h"
#include "passes/gbuffer.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// A glTF file built in memory: one binary buffer (written beside the .gltf) and the JSON.
class GltfWriter {
 public:
  GltfWriter() { json_ = {{"asset", {{"version", "2.0"}}}, {"scene", 0}, {"scenes", {{{"nodes", Json::array()}}}}}; }
  Json& json() { return json_; }

  // Appends raw bytes as a buffer view (4-byte aligned); returns its index.
  int View(const void* data, size_t bytes) {
    while (bin_.size() % 4) bin_.push_back(0);
    const size_t offset = bin_.size();
    bin_.insert(bin_.end(), static_cast<const uint8_t*>(data), static_cast<const uint8_t*>(data) + bytes);
    json_["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
    return int(json_["bufferViews"].size()) - 1;
  }
  template <class T>
  int Accessor(const std::vector<T>& values, int componentType, const std::string& type, size_t count,
               bool normalized = false) {
    const int view = View(values.data(), values.size() * sizeof(T));
    Json a = {{"bufferView", view}, {"componentType", componentType}, {"type", type}, {"count", count}};
    if (normalized) a["normalized"] = true;
    if (type == "VEC3" && componentType == 5126) {  // POSITION needs min and max
      std::vector<float> lo(3, 1e30f), hi(3, -1e30f);
      for (size_t i = 0; i < values.size(); ++i) {
        lo[i % 3] = std::min(lo[i % 3], float(values[i]));
        hi[i % 3] = std::max(hi[i % 3], float(values[i]));
      }
      a["min"] = lo, a["max"] = hi;
    }
    json_["accessors"].push_back(a);
    return int(json_["accessors"].size()) - 1;
  }
  // A node with a mesh of one primitive; returns the node's index (added to the scene if `root`).
  int MeshNode(const Json& primitive, const Json& node = Json::object(), bool root = true) {
    json_["meshes"].push_back({{"primitives", {primitive}}});
    Json n = node;
    n["mesh"] = json_["meshes"].size() - 1;
    json_["nodes"].push_back(n);
    const int index = int(json_["nodes"].size()) - 1;
    if (root) json_["scenes"][0]["nodes"].push_back(index);
    return index;
  }
  // A unit quad in z = 0 facing +z, (0,0)-(1,1), with normals and UVs (v down, as glTF's).
  Json Quad(int material = -1) {
    const std::vector<float> p = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const std::vector<float> n = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const std::vector<float> uv = {0, 1, 1, 1, 1, 0, 0, 0};
    const std::vector<uint16_t> idx = {0, 1, 2, 0, 2, 3};
    Json prim = {{"attributes",
                  {{"POSITION", Accessor(p, 5126, "VEC3", 4)},
                   {"NORMAL", Accessor(n, 5126, "VEC3", 4)},
                   {"TEXCOORD_0", Accessor(uv, 5126, "VEC2", 4)}}},
                 {"indices", Accessor(idx, 5123, "SCALAR", 6)}};
    if (material >= 0) prim["material"] = material;
    return prim;
  }
  fs::path Write(const fs::path& gltf) {
    const fs::path bin = gltf.parent_path() / (gltf.stem().string() + ".bin");
    json_["buffers"] = {{{"uri", bin.filename().string()}, {"byteLength", bin_.size()}}};
    std::ofstream(bin, std::ios::binary)
        .write(reinterpret_cast<const char*>(bin_.data()), std::streamsize(bin_.size()));
    test::WriteText(gltf, json_.dump(1));
    return gltf;
  }

  // The binary container: a JSON chunk and the buffer as the BIN chunk.
  fs::path WriteGlb(const fs::path& glb) {
    Json json = json_;
    json["buffers"] = {{{"byteLength", bin_.size()}}};
    std::string text = json.dump();
    while (text.size() % 4) text.push_back(' ');
    std::vector<uint8_t> bin = bin_;
    while (bin.size() % 4) bin.push_back(0);
    std::string out;
    const auto word = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    word(0x46546C67u), word(2), word(uint32_t(12 + 8 + text.size() + 8 + bin.size()));
    word(uint32_t(text.size())), word(0x4E4F534Au), out += text;
    word(uint32_t(bin.size())), word(0x004E4942u), out.append(reinterpret_cast<const char*>(bin.data()), bin.size());
    std::ofstream(glb, std::ios::binary).write(out.data(), std::streamsize(out.size()));
    return glb;
  }

 private:
  Json json_;
  std::vector<uint8_t> bin_;
};

void WriteRgbaPng(const fs::path& file, int width, int height, const std::vector<uint8_t>& rgba) {
  auto out = OIIO::ImageOutput::create(file.string());
  REQUIRE(out);
  REQUIRE(out->open(file.string(), OIIO::ImageSpec(width, height, 4, OIIO::TypeDesc::UINT8)));
  REQUIRE(out->write_image(OIIO::TypeDesc::UINT8, rgba.data()));
  out->close();
}

std::string LoadError(const fs::path& file) {
  return test::InputErrorOf([&] { LoadGltfModel(file); });
}

TEST_CASE("glTF: every accessor component type, normalized and quantized, indices of each width, strips and fans",
          "[gltf]") {
  test::ScratchDir dir("gltf-accessors");
  // The same right triangle (0,0,0) (2,0,0) (0,2,0) through every encoding of its positions.
  struct Case {
    const char* name;
    int componentType;
    bool normalized;
    std::vector<int64_t> codes;
  };
  const Case cases[] = {
      {"float", 5126, false, {}},
      {"byte", 5120, false, {0, 0, 0, 2, 0, 0, 0, 2, 0}},
      {"ubyte", 5121, false, {0, 0, 0, 2, 0, 0, 0, 2, 0}},
      {"short", 5122, false, {0, 0, 0, 2, 0, 0, 0, 2, 0}},
      {"ushort", 5123, false, {0, 0, 0, 2, 0, 0, 0, 2, 0}},
      {"byte normalized", 5120, true, {0, 0, 0, 127, 0, 0, 0, 127, 0}},
      {"ubyte normalized", 5121, true, {0, 0, 0, 255, 0, 0, 0, 255, 0}},
      {"short normalized", 5122, true, {0, 0, 0, 32767, 0, 0, 0, 32767, 0}},
      {"ushort normalized", 5123, true, {0, 0, 0, 65535, 0, 0, 0, 65535, 0}},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    GltfWriter w;
    int position = 0;
    const auto padded = [](auto values) {  // vertex attributes are aligned to 4 bytes per element
      return values;
    };
    if (c.componentType == 5126) {
      position = w.Accessor(std::vector<float>{0, 0, 0, 2, 0, 0, 0, 2, 0}, 5126, "VEC3", 3);
    } else if (c.componentType == 5120 || c.componentType == 5121) {
      std::vector<uint8_t> bytes;
      for (size_t v = 0; v < 3; ++v) {
        for (size_t k = 0; k < 3; ++k) bytes.push_back(uint8_t(c.codes[3 * v + k]));
        bytes.push_back(0);  // padding to the 4-byte vertex stride
      }
      position = w.Accessor(padded(bytes), c.componentType, "VEC3", 3, c.normalized);
      w.json()["bufferViews"][w.json()["accessors"][size_t(position)]["bufferView"].get<size_t>()]["byteStride"] = 4;
    } else {
      std::vector<uint16_t> shorts;
      for (size_t v = 0; v < 3; ++v) {
        for (size_t k = 0; k < 3; ++k) shorts.push_back(uint16_t(c.codes[3 * v + k]));
        shorts.push_back(0);
      }
      position = w.Accessor(shorts, c.componentType, "VEC3", 3, c.normalized);
      w.json()["bufferViews"][w.json()["accessors"][size_t(position)]["bufferView"].get<size_t>()]["byteStride"] = 8;
    }
    if (c.componentType != 5126) w.json()["extensionsRequired"] = {"KHR_mesh_quantization"};
    if (c.componentType != 5126) w.json()["extensionsUsed"] = {"KHR_mesh_quantization"};
    w.MeshNode({{"attributes", {{"POSITION", position}}}});
    const GltfModel m = LoadGltfModel(w.Write(dir / "tri.gltf"));
    REQUIRE(m.mesh.TriangleCount() == 1);
    const glm::vec3 expected[3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = m.mesh.positions[m.mesh.indices[size_t(k)]];
      // Normalized codes reach 1 (the largest code), the others their value.
      CHECK(p.x == Approx(expected[k].x * (c.normalized ? 0.5f : 1.0f)).margin(1e-6));
      CHECK(p.y == Approx(expected[k].y * (c.normalized ? 0.5f : 1.0f)).margin(1e-6));
      // No NORMAL: the flat normal of the face.
      CHECK(m.mesh.normals[m.mesh.indices[size_t(k)]] == glm::vec3(0, 0, 1));
    }
  }

  // A quad of four vertices through each index width and as a strip and a fan: two triangles, the
  // same four corners, counter-clockwise (+z).
  const std::vector<float> quad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  struct Topology {
    int mode;
    std::vector<uint32_t> order;
  };
  for (const Topology& t : {Topology{4, {0, 1, 2, 0, 2, 3}}, Topology{5, {1, 2, 0, 3}}, Topology{6, {0, 1, 2, 3}}}) {
    for (const int indexType : {5121, 5123, 5125}) {
      CAPTURE(t.mode, indexType);
      GltfWriter w;
      const int position = w.Accessor(quad, 5126, "VEC3", 4);
      int indices = 0;
      if (indexType == 5121)
        indices = w.Accessor(std::vector<uint8_t>(t.order.begin(), t.order.end()), indexType, "SCALAR", t.order.size());
      if (indexType == 5123)
        indices =
            w.Accessor(std::vector<uint16_t>(t.order.begin(), t.order.end()), indexType, "SCALAR", t.order.size());
      if (indexType == 5125) indices = w.Accessor(t.order, indexType, "SCALAR", t.order.size());
      w.MeshNode({{"attributes", {{"POSITION", position}}}, {"indices", indices}, {"mode", t.mode}});
      const GltfModel m = LoadGltfModel(w.Write(dir / "quad.gltf"));
      REQUIRE(m.mesh.TriangleCount() == 2);
      for (size_t tri = 0; tri < 2; ++tri) {
        const glm::vec3 a = m.mesh.positions[m.mesh.indices[3 * tri]],
                        b = m.mesh.positions[m.mesh.indices[3 * tri + 1]],
                        c = m.mesh.positions[m.mesh.indices[3 * tri + 2]];
        CHECK(glm::cross(b - a, c - a).z == Approx(1.0f));
      }
    }
  }

  // Sparse substitution: the float triangle's third vertex moved to (0, 3, 0).
  GltfWriter w;
  const int position = w.Accessor(std::vector<float>{0, 0, 0, 2, 0, 0, 0, 2, 0}, 5126, "VEC3", 3);
  const int sparseIndices = w.View(std::vector<uint16_t>{2, 0}.data(), 4);
  const int sparseValues = w.View(std::vector<float>{0, 3, 0}.data(), 12);
  w.json()["accessors"][size_t(position)]["sparse"] = {
      {"count", 1},
      {"indices", {{"bufferView", sparseIndices}, {"componentType", 5123}}},
      {"values", {{"bufferView", sparseValues}}}};
  w.MeshNode({{"attributes", {{"POSITION", position}}}});
  const GltfModel sparse = LoadGltfModel(w.Write(dir / "sparse.gltf"));
  CHECK(sparse.mesh.positions[sparse.mesh.indices[2]] == glm::vec3(0, 3, 0));
}

TEST_CASE("glTF: the node hierarchy's transforms, matrices and TRS, mirrored instances turned back", "[gltf]") {
  test::ScratchDir dir("gltf-nodes");
  GltfWriter w;
  const Json quad = w.Quad();
  // Parent: a matrix translating by (10, 0, 0); child: TRS, rotated 90 degrees about +y, scaled 2,
  // translated (0, 5, 0); a second instance of the same mesh mirrored in x.
  const int child = w.MeshNode(
      quad, {{"translation", {0, 5, 0}}, {"rotation", {0, std::sqrt(0.5), 0, std::sqrt(0.5)}}, {"scale", {2, 2, 2}}},
      false);
  w.json()["nodes"].push_back({{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1}}, {"children", {child}}});
  w.json()["scenes"][0]["nodes"].push_back(w.json()["nodes"].size() - 1);
  w.json()["nodes"].push_back({{"mesh", 0}, {"scale", {-1, 1, 1}}});
  w.json()["scenes"][0]["nodes"].push_back(w.json()["nodes"].size() - 1);
  const GltfModel m = LoadGltfModel(w.Write(dir / "nodes.gltf"));
  REQUIRE(m.mesh.TriangleCount() == 4);
  // Vertex (1, 0, 0) of the quad: rotated to (0, 0, -1), scaled to (0, 0, -2), moved to (10, 5, -2).
  const glm::vec3 moved = m.mesh.positions[1];
  CHECK(moved.x == Approx(10.0f));
  CHECK(moved.y == Approx(5.0f));
  CHECK(moved.z == Approx(-2.0f));
  CHECK(m.mesh.normals[1].x == Approx(1.0f));  // +z rotated about +y
  for (size_t t = 0; t < 4; ++t) {
    const glm::vec3 a = m.mesh.positions[m.mesh.indices[3 * t]], b = m.mesh.positions[m.mesh.indices[3 * t + 1]],
                    c = m.mesh.positions[m.mesh.indices[3 * t + 2]];
    // Every triangle still faces where its normals point.
    CHECK(glm::dot(glm::cross(b - a, c - a), m.mesh.normals[m.mesh.indices[3 * t]]) > 0.0f);
  }
}

TEST_CASE(
    "glTF: materials: factors, the metallic-roughness texture's B and G, alpha modes, two sides, texture "
    "transform, COLOR_0, emission and occlusion warned",
    "[gltf]") {
  test::ScratchDir dir("gltf-materials");
  // 2x1 RGBA texture: texel 0 (R 10, G 100, B 200, A 255), texel 1 (R 0, G 0, B 0, A 0).
  WriteRgbaPng(dir / "tex.png", 2, 1, {10, 100, 200, 255, 0, 0, 0, 0});
  GltfWriter w;
  Json& j = w.json();
  j["images"] = {{{"uri", "tex.png"}}};
  j["textures"] = {{{"source", 0}, {"sampler", 0}}};
  j["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33648}}};  // CLAMP_TO_EDGE, MIRRORED_REPEAT
  j["materials"] = Json::parse(R"([
      {"name": "factors", "doubleSided": true, "emissiveFactor": [1, 0, 0],
       "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1.0, 1.0], "metallicFactor": 0.75,
                                "roughnessFactor": 0.2}},
      {"name": "textured", "alphaMode": "MASK", "alphaCutoff": 0.4, "occlusionTexture": {"index": 0},
       "pbrMetallicRoughness": {
         "baseColorTexture": {"index": 0,
                              "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "scale": [2, 1]}}},
         "metallicRoughnessTexture": {"index": 0,
                              "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "scale": [2, 1]}}}}},
      {"name": "hidden", "alphaMode": "MASK", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.3]}},
      {"name": "blend", "alphaMode": "BLEND"}])");
  j["extensionsUsed"] = {"KHR_texture_transform"};
  w.MeshNode(w.Quad(0));
  w.MeshNode(w.Quad(1));
  w.MeshNode(w.Quad(2));
  Json coloured = w.Quad(3);
  coloured["attributes"]["COLOR_0"] = w.Accessor(
      std::vector<uint8_t>{255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255}, 5121, "VEC4", 4, true);
  w.MeshNode(coloured);
  const GltfModel m = LoadGltfModel(w.Write(dir / "materials.gltf"));

  const Material& factors = m.materials[0];
  CHECK(factors.name == "factors");
  CHECK(factors.baseColor == glm::vec3(0.5f, 0.25f, 1.0f));
  CHECK(factors.metallic == 0.75f);
  CHECK(factors.roughness == 0.2f);
  CHECK(factors.twoSided);
  CHECK(factors.baseColorTexture == kNoTexture);

  const Material& textured = m.materials[1];
  CHECK_FALSE(textured.twoSided);
  REQUIRE(textured.baseColorTexture != kNoTexture);
  REQUIRE(textured.metallicTexture != kNoTexture);
  REQUIRE(textured.roughnessTexture != kNoTexture);
  CHECK(textured.alphaTexture == textured.baseColorTexture);
  CHECK(textured.alphaCutoff == Approx(0.4f));
  // Metallic from B, roughness from G, both read from R by the resolve (linear); colour sRGB.
  const auto texel = [&](int32_t t, int x) { return m.textures[size_t(t)].texels[4 * size_t(x)]; };
  CHECK(texel(textured.metallicTexture, 0) == 200);
  CHECK(texel(textured.roughnessTexture, 0) == 100);
  CHECK(texel(textured.baseColorTexture, 0) == 10);
  CHECK(m.textures[size_t(textured.baseColorTexture)].encoding == TextureEncoding::kSrgb);
  CHECK(m.textures[size_t(textured.metallicTexture)].encoding == TextureEncoding::kLinear);
  CHECK(m.textures[size_t(textured.baseColorTexture)].wrapU == TextureWrap::kClamp);
  CHECK(m.textures[size_t(textured.baseColorTexture)].wrapV == TextureWrap::kMirror);
  // KHR_texture_transform u' = 2 u + 0.5; glTF's v = 1 - ssgi's.
  CHECK(m.mesh.uvs[4 + 1].x == Approx(2.5f));
  CHECK(m.mesh.uvs[4 + 0].x == Approx(0.5f));
  CHECK(m.mesh.uvs[4 + 0].y == Approx(0.0f));
  CHECK(m.mesh.uvs[4 + 2].y == Approx(1.0f));

  // "hidden": a constant alpha of 0.3 below the default cut-off 0.5, not drawn: 3 quads in all.
  CHECK(m.mesh.TriangleCount() == 6);
  // COLOR_0 (normalized bytes) multiplies the base colour: a material of its own.
  CHECK(m.materials.back().vertexColors);
  REQUIRE(m.mesh.colors.size() == m.mesh.positions.size());
  CHECK(m.mesh.colors.back() == glm::vec3(1.0f));
  CHECK(m.mesh.colors[m.mesh.colors.size() - 4] == glm::vec3(1.0f, 0.0f, 0.0f));
  CHECK(m.mesh.colors[0] == glm::vec3(1.0f));  // primitives without COLOR_0 are white

  const auto warned = [&](const std::string& text) {
    return std::count_if(m.warnings.begin(), m.warnings.end(),
                         [&](const std::string& x) { return x.find(text) != std::string::npos; });
  };
  CHECK(warned("emission is not rendered") == 1);
  CHECK(warned("occlusionTexture is not used") == 1);
  CHECK(warned("BLEND is drawn as MASK") == 1);
  for (const std::string& x : m.warnings) CHECK_THAT(x, Catch::StartsWith((dir / "materials.gltf").string() + ": "));
}

TEST_CASE("glTF: punctual lights in ssgi's units, spot cones, the first camera with its aspect ratio, orthographic",
          "[gltf]") {
  test::ScratchDir dir("gltf-lights");
  GltfWriter w;
  Json& j = w.json();
  w.MeshNode(w.Quad());
  j["extensionsUsed"] = {"KHR_lights_punctual"};
  j["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "directional"}, {"intensity", 683.0 * 3}, {"color", {1, 0.5, 0.25}}},
      {{"type", "spot"}, {"intensity", 683.0 * 10}, {"spot", {{"innerConeAngle", 0.25}, {"outerConeAngle", 0.5}}}},
      {{"type", "point"}, {"intensity", 683.0 * 7}}};
  // A sun pointing down (-z rotated to -y: 90 degrees about +x... -90), a spot at (0, 4, 0) down, a point at (1, 2, 3).
  const double h = std::sqrt(0.5);
  for (int light = 0; light < 3; ++light) {
    Json node = {{"extensions", {{"KHR_lights_punctual", {{"light", light}}}}}};
    if (light < 2) node["rotation"] = {-h, 0, 0, h};
    node["translation"] = light == 2 ? Json{1, 2, 3} : Json{0, 4, 0};
    j["nodes"].push_back(node);
    j["scenes"][0]["nodes"].push_back(j["nodes"].size() - 1);
  }
  j["cameras"] = {
      {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}, {"aspectRatio", 2.0}}}},
      {{"type", "orthographic"}, {"orthographic", {{"xmag", 2}, {"ymag", 1}, {"znear", 0.5}, {"zfar", 20}}}}};
  j["nodes"].push_back({{"camera", 0}, {"translation", {0, 0, 5}}});
  j["scenes"][0]["nodes"].push_back(j["nodes"].size() - 1);
  j["nodes"].push_back({{"camera", 1}, {"translation", {0, 0, 7}}});
  j["scenes"][0]["nodes"].push_back(j["nodes"].size() - 1);
  const fs::path file = w.Write(dir / "lights.gltf");
  const GltfModel m = LoadGltfModel(file);
  REQUIRE(m.directionalLights.size() == 1);
  REQUIRE(m.spotLights.size() == 1);
  REQUIRE(m.pointLights.size() == 1);
  // lux / 683 = W/m^2, candela / 683 = W/sr.
  CHECK(m.directionalLights[0].irradiance.x == Approx(3.0f));
  CHECK(m.directionalLights[0].irradiance.y == Approx(1.5f));
  CHECK(m.directionalLights[0].direction.y == Approx(-1.0f));
  CHECK(m.spotLights[0].intensity.x == Approx(10.0f));
  CHECK(m.spotLights[0].position.y == Approx(4.0f));
  CHECK(m.spotLights[0].innerConeDegrees == Approx(0.25 * 180 / 3.14159265358979));
  CHECK(m.spotLights[0].outerConeDegrees == Approx(0.5 * 180 / 3.14159265358979));
  CHECK(m.pointLights[0].intensity.x == Approx(7.0f));
  CHECK(m.pointLights[0].position == glm::vec3(1, 2, 3));
  REQUIRE(m.cameras.size() == 2);
  CHECK(m.cameras[0].desc.position == glm::vec3(0, 0, 5));
  CHECK(m.cameras[0].desc.target.z == Approx(4.0f));
  CHECK(m.cameras[0].desc.fovYDegrees == Approx(0.5 * 180 / 3.14159265358979));
  CHECK(m.cameras[0].aspectRatio == 2.0f);
  // Orthographic: a narrow perspective whose view height at the middle of [znear, zfar] is 2 ymag.
  const CameraDesc& ortho = m.cameras[1].desc;
  const double middle = double(glm::length(ortho.target - ortho.position)) + 0.5 * (0.5 + 20);
  CHECK(2.0 * middle * std::tan(glm::radians(double(ortho.fovYDegrees)) / 2) == Approx(2.0).epsilon(1e-4));
  CHECK(m.cameras[1].aspectRatio == 2.0f);

  // The bare file: its first camera and lights, the image's height from the aspect ratio; a scene
  // file may pick another camera.
  const SceneFile scene = LoadSceneFile(file);
  CHECK(scene.scene.camera.position == glm::vec3(0, 0, 5));
  CHECK(scene.scene.pointLights.size() == 1);
  bool height = false;
  for (const RenderBlockEntry& e : scene.render) height |= e.key == "height" && e.json == "512";
  CHECK(height);
  test::WriteText(dir / "scene.json", R"({"objects": [{"gltf": "lights.gltf", "camera": 1,
      "transform": {"translate": [0, 1, 0]}}]})");
  const Scene picked = LoadScene(dir / "scene.json");
  CHECK(picked.camera.position.y == Approx(1.0f));
  CHECK(picked.camera.position.z > 7.0f);
  CHECK(picked.pointLights[0].position == glm::vec3(1, 3, 3));
  test::WriteText(dir / "bad_camera.json", R"({"objects": [{"gltf": "lights.gltf", "camera": 2}]})");
  CHECK_THAT(test::InputErrorOf([&] { LoadScene(dir / "bad_camera.json"); }), Catch::Contains("camera"));
  test::WriteText(dir / "both.json", R"({"objects": [{"gltf": "lights.gltf", "obj": "x.obj"}]})");
  CHECK_THAT(test::InputErrorOf([&] { LoadScene(dir / "both.json"); }), Catch::Contains("exactly one of"));
  // A scene file's own point light, beside the file's, and the one warning.
  test::WriteText(dir / "point.json", R"({"lights": [{"type": "point", "position": [0, 5, 0], "radius": 0.1,
      "intensity": [2, 3, 4]}], "objects": [{"gltf": "lights.gltf"}]})");
  const Scene point = LoadScene(dir / "point.json");
  REQUIRE(point.pointLights.size() == 2);
  CHECK(point.pointLights[0].position == glm::vec3(0, 5, 0));
  CHECK(point.pointLights[0].radius == 0.1f);
  CHECK(point.pointLights[0].intensity == glm::vec3(2, 3, 4));
  CHECK(std::count_if(point.warnings.begin(), point.warnings.end(), [](const std::string& line) {
          return line.find("point lights are not shadowed") != std::string::npos;
        }) == 1);
}

TEST_CASE("glTF: generated tangents follow the UVs' u direction with the UV triangle's handedness", "[gltf]") {
  // A quad in the xz plane facing +y with u along +x: tangent +x. Its mirror image in u: tangent -x
  // ... with the sign flipped, so the bitangent w cross(n, t) still points along +v.
  for (const float uDirection : {1.0f, -1.0f}) {
    Mesh mesh;
    const glm::vec3 p[4] = {{0, 0, 0}, {1, 0, 0}, {1, 0, -1}, {0, 0, -1}};
    for (int i = 0; i < 4; ++i) {
      mesh.positions.push_back(p[i]);
      mesh.normals.push_back({0, 1, 0});
      mesh.uvs.push_back({uDirection * p[i].x, -p[i].z});
    }
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.materials = {0, 0};
    GenerateTangents(mesh);
    REQUIRE(mesh.tangents.size() == 4);
    for (const glm::vec4& t : mesh.tangents) {
      CHECK(t.x == Approx(uDirection));
      CHECK(t.w == uDirection);
      const glm::vec3 bitangent = glm::cross(glm::vec3(0, 1, 0), glm::vec3(t)) * t.w;
      CHECK(bitangent.z == Approx(-1.0f));  // +v is -z
    }
  }
}

// Bad input: each refused with one line naming the file.
TEST_CASE("glTF: bad input is refused with one line naming the file and the problem", "[gltf][errors]") {
  test::ScratchDir dir("gltf-errors");
  const auto quadWith = [&](const std::string& name, const std::function<void(GltfWriter&, Json&)>& edit) {
    GltfWriter w;
    Json prim = w.Quad();
    edit(w, prim);
    w.MeshNode(prim);
    return LoadError(w.Write(dir / name));
  };
  const auto oneLine = [](const std::string& m) { return m.find('\n') == std::string::npos && !m.empty(); };
  std::vector<std::string> messages;
  const auto expect = [&](const std::string& message, const std::string& file, const std::string& problem) {
    CAPTURE(message);
    CHECK(oneLine(message));
    CHECK_THAT(message, Catch::Contains(file) && Catch::Contains(problem));
  };
  test::WriteText(dir / "syntax.gltf", R"({"asset": {"version": "2.0"}, "meshes": [)");
  expect(LoadError(dir / "syntax.gltf"), "syntax.gltf", "");
  expect(LoadError(dir / "absent.gltf"), "absent.gltf", "not found");
  test::WriteText(dir / "nobin.gltf",
                  R"({"asset": {"version": "2.0"}, "buffers": [{"uri": "gone.bin", "byteLength": 12}]})");
  expect(LoadError(dir / "nobin.gltf"), "nobin.gltf", "gone.bin");
  expect(quadWith("noimage.gltf",
                  [](GltfWriter& w, Json& prim) {
                    w.json()["images"] = {{{"uri", "gone.png"}}};
                    w.json()["textures"] = {{{"source", 0}}};
                    w.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
                    prim["material"] = 0;
                  }),
         "noimage.gltf", "gone.png");
  expect(quadWith("range.gltf",
                  [](GltfWriter& w, Json& prim) {
                    prim["indices"] = w.Accessor(std::vector<uint16_t>{0, 1, 9}, 5123, "SCALAR", 3);
                  }),
         "range.gltf", "index 9");
  expect(quadWith("overrun.gltf", [](GltfWriter& w, Json&) { w.json()["accessors"][0]["count"] = 400; }),
         "overrun.gltf", "reads past the end");
  expect(quadWith("accessor.gltf", [](GltfWriter&, Json& prim) { prim["attributes"]["NORMAL"] = 99; }), "accessor.gltf",
         "accessor 99");
  expect(quadWith("nan.gltf",
                  [](GltfWriter& w, Json& prim) {
                    const float nan = std::nanf("");
                    prim["attributes"]["POSITION"] =
                        w.Accessor(std::vector<float>{0, 0, 0, 1, 0, 0, 1, nan, 0, 0, 1, 0}, 5126, "VEC3", 4);
                  }),
         "nan.gltf", "non-finite");
  expect(quadWith("required.gltf",
                  [](GltfWriter& w, Json&) { w.json()["extensionsRequired"] = {"EXT_meshopt_compression"}; }),
         "required.gltf", "EXT_meshopt_compression");
  expect(quadWith("draco.gltf",
                  [](GltfWriter& w, Json&) { w.json()["extensionsRequired"] = {"KHR_draco_mesh_compression"}; }),
         "draco.gltf", "Draco");
  expect(quadWith("lines.gltf", [](GltfWriter&, Json& prim) { prim["mode"] = 1; }), "lines.gltf", "points or lines");
  expect(quadWith("points.gltf", [](GltfWriter&, Json& prim) { prim["mode"] = 0; }), "points.gltf", "points or lines");
  expect(quadWith("cycle.gltf",
                  [](GltfWriter& w, Json&) {
                    // Node 0 (written before the quad's node 1) is its own child.
                    w.json()["nodes"][0]["children"] = Json::array({0});
                    w.json()["scenes"][0]["nodes"].push_back(0);
                  }),
         "cycle.gltf", "cycle");
  expect(quadWith("version.gltf", [](GltfWriter& w, Json&) { w.json()["asset"]["version"] = "1.0"; }), "version.gltf",
         "");
}

// As the OBJ loader's: mutated bytes of a valid .gltf and .glb must load or be refused with one
// InputError line, never crash, hang or throw anything else.
TEST_CASE("glTF: mutated files load or are refused with one line", "[gltf][errors]") {
  test::ScratchDir dir("gltf-fuzz");
  GltfWriter w;
  w.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 0.5, 0.5, 1}}}}}};
  w.MeshNode(w.Quad(0), {{"translation", {0, 1, 0}}});
  for (const fs::path& valid : {w.Write(dir / "valid.gltf"), w.WriteGlb(dir / "valid.glb")}) {
    std::ifstream in(valid, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    REQUIRE(LoadError(valid).empty());
    const fs::path target = dir / ("mutated" + valid.extension().string());
    std::mt19937 rng(40);
    int refused = 0;
    for (int trial = 0; trial < 300; ++trial) {
      std::string mutated = text;
      const int edits = 1 + int(rng() % 4);
      for (int e = 0; e < edits; ++e) {
        const size_t at = rng() % mutated.size();
        switch (rng() % 4) {
          case 0:
            mutated[at] = char("0123456789-.,:[]{}\"e"[rng() % 20]);
            break;
          case 1:
            mutated.erase(at, 1 + rng() % 8);
            break;
          case 2:
            mutated.insert(at, std::string(1, char(rng() % 128)));
            break;
          default:
            mutated[at] = char(rng());
            break;
        }
      }
      test::WriteText(target, mutated);
      std::string message;
      REQUIRE_NOTHROW(message = LoadError(target));
      if (!message.empty()) {
        ++refused;
        CHECK(message.find('\n') == std::string::npos);
        CHECK_THAT(message, Catch::Contains(target.filename().string()));
      }
    }
    CHECK(refused > 0);
  }
}

}  // namespace
}  // namespace ssgi
