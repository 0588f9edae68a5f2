#include "core/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <iterator>
#include <map>
#include <set>
#include <tuple>
#include <unordered_map>

#include "core/error.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;

// The extensions ssgi reads; KHR_materials_emissive_strength only scales an emission ssgi does not
// render (docs/user-guide.md "glTF files").
const std::set<std::string> kSupportedExtensions = {"KHR_lights_punctual", "KHR_texture_transform",
                                                    "KHR_mesh_quantization", "KHR_materials_emissive_strength"};

constexpr const char* kDracoRefusal =
    "Draco-compressed meshes (KHR_draco_mesh_compression) are not supported: Debian's tinygltf is built without "
    "Draco";

// tinygltf's messages may span lines and end with one; the first line, with the rest's count.
std::string OneLine(const std::string& text) {
  std::string line = text.substr(0, text.find('\n'));
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
  return line.empty() ? "cannot be read as glTF 2.0" : line;
}

class Loader {
 public:
  Loader(const fs::path& file, const tinygltf::Model& model) : file_(file), gltf_(model) {}

  GltfModel Load();

 private:
  [[noreturn]] void Fail(const std::string& problem) const { throw InputError(file_, problem); }
  void Warn(const std::string& message) {
    const std::string line = file_.string() + ": " + message;
    if (std::find(out_.warnings.begin(), out_.warnings.end(), line) == out_.warnings.end())
      out_.warnings.push_back(line);
  }

  void CheckExtensions();
  std::vector<float> ReadAccessor(int index, const std::string& what, std::initializer_list<int> types,
                                  int& components) const;
  std::vector<uint32_t> ReadIndices(int index, size_t vertexCount, const std::string& what) const;
  void VisitNode(int node, const glm::dmat4& parent, std::vector<int>& path);
  void AddPrimitive(const tinygltf::Primitive& primitive, const glm::dmat4& transform, const std::string& what);
  int32_t TextureFor(int textureIndex, int role, const std::string& what);
  uint32_t MaterialFor(int materialIndex, bool vertexColors, bool& invisible);
  void AddLight(int light, const glm::dmat4& transform);
  void AddCamera(int camera, const glm::dmat4& transform);

  const fs::path file_;
  const tinygltf::Model& gltf_;
  GltfModel out_;
  // (image, role, wrap u, wrap v) -> out_.textures
  using TextureKey = std::tuple<int, int, TextureWrap, TextureWrap>;
  std::map<TextureKey, int32_t> textures_;
  std::map<std::pair<int, bool>, uint32_t> materials_;       // (material, vertex colours) -> out_.materials
  std::map<std::pair<int, bool>, bool> invisibleMaterials_;  // constant alpha below the cut-off
  bool normalMapped_ = false;
};

// How an image is turned into a Texture: which channels, which encoding.
enum TextureRole : int { kBaseColorRole, kMetallicRole, kRoughnessRole, kNormalRole };

void Loader::CheckExtensions() {
  for (const std::string& name : gltf_.extensionsRequired) {
    if (name == "KHR_draco_mesh_compression") Fail(kDracoRefusal);
    if (!kSupportedExtensions.count(name)) Fail("requires extension " + name + ", which ssgi does not support");
  }
  for (const std::string& name : gltf_.extensionsUsed)
    if (name.rfind("KHR_materials_", 0) == 0 && !kSupportedExtensions.count(name))
      Warn(name + " is ignored: ssgi's materials are metallic-roughness only");
}

size_t ComponentBytes(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
  }
}

int ComponentCount(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    default:
      return 0;
  }
}

// One component as a float: normalized integers map to [0, 1] or [-1, 1] as the spec says
// (max(c / 127, -1) for signed bytes), other integers keep their value (KHR_mesh_quantization).
float ReadComponent(const unsigned char* at, int type, bool normalized) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const auto c = int8_t(*at);
      return normalized ? std::max(float(c) / 127.0f, -1.0f) : float(c);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized ? float(*at) / 255.0f : float(*at);
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t c;
      std::memcpy(&c, at, 2);
      return normalized ? std::max(float(c) / 32767.0f, -1.0f) : float(c);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t c;
      std::memcpy(&c, at, 2);
      return normalized ? float(c) / 65535.0f : float(c);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t c;
      std::memcpy(&c, at, 4);
      return normalized ? float(double(c) / 4294967295.0) : float(c);
    }
    default: {
      float c;
      std::memcpy(&c, at, 4);
      return c;
    }
  }
}

// The bytes of `count` elements of `elementBytes` each, `stride` apart from `offset` in buffer view
// `view`, checked against the view and its buffer; `what` names the accessor in the message.
const unsigned char* ViewBytes(const tinygltf::Model& gltf, const fs::path& file, int view, size_t offset, size_t count,
                               size_t elementBytes, size_t stride, const std::string& what) {
  if (view < 0 || size_t(view) >= gltf.bufferViews.size())
    throw InputError(file, what + " names buffer view " + std::to_string(view) + ", which does not exist");
  const tinygltf::BufferView& bv = gltf.bufferViews[size_t(view)];
  if (bv.buffer < 0 || size_t(bv.buffer) >= gltf.buffers.size())
    throw InputError(file, "buffer view " + std::to_string(view) + " names a buffer that does not exist");
  const tinygltf::Buffer& buffer = gltf.buffers[size_t(bv.buffer)];
  if (bv.byteOffset > buffer.data.size() || bv.byteLength > buffer.data.size() - bv.byteOffset)
    throw InputError(file, "buffer view " + std::to_string(view) + " lies outside its buffer (" +
                               std::to_string(buffer.data.size()) + " bytes)");
  if (count == 0) return buffer.data.data() + bv.byteOffset;
  // count - 1 strides and one element from offset, each term checked before it is added.
  const size_t length = bv.byteLength;
  if (offset > length || elementBytes > length - offset || (count - 1) > (length - offset - elementBytes) / stride)
    throw InputError(file, what + " reads past the end of buffer view " + std::to_string(view) + " (" +
                               std::to_string(bv.byteLength) + " bytes)");
  return buffer.data.data() + bv.byteOffset + offset;
}

std::vector<float> Loader::ReadAccessor(int index, const std::string& what, std::initializer_list<int> types,
                                        int& components) const {
  if (index < 0 || size_t(index) >= gltf_.accessors.size())
    Fail(what + " names accessor " + std::to_string(index) + ", which does not exist");
  const tinygltf::Accessor& a = gltf_.accessors[size_t(index)];
  const std::string name = what + " (accessor " + std::to_string(index) + ")";
  components = ComponentCount(a.type);
  if (components == 0 || std::find(types.begin(), types.end(), a.type) == types.end())
    Fail(name + " has a type its attribute does not allow");
  const size_t bytes = ComponentBytes(a.componentType);
  if (bytes == 0) Fail(name + " has an unknown component type " + std::to_string(a.componentType));
  const size_t elementBytes = bytes * size_t(components);
  if (a.count > (size_t(1) << 31)) Fail(name + " has more than 2^31 elements");
  std::vector<float> values(a.count * size_t(components), 0.0f);
  if (a.bufferView >= 0) {
    const size_t viewStride =
        size_t(a.bufferView) < gltf_.bufferViews.size() ? gltf_.bufferViews[size_t(a.bufferView)].byteStride : 0;
    const size_t stride = viewStride != 0 ? viewStride : elementBytes;
    const unsigned char* data =
        ViewBytes(gltf_, file_, a.bufferView, a.byteOffset, a.count, elementBytes, stride, name);
    for (size_t i = 0; i < a.count; ++i)
      for (int c = 0; c < components; ++c)
        values[i * size_t(components) + size_t(c)] =
            ReadComponent(data + i * stride + size_t(c) * bytes, a.componentType, a.normalized);
  }
  if (a.sparse.isSparse) {
    const size_t count = size_t(std::max(a.sparse.count, 0));
    const int indexType = a.sparse.indices.componentType;
    const size_t indexBytes = ComponentBytes(indexType);
    if (indexBytes == 0 || indexType == TINYGLTF_COMPONENT_TYPE_FLOAT || indexType == TINYGLTF_COMPONENT_TYPE_BYTE ||
        indexType == TINYGLTF_COMPONENT_TYPE_SHORT)
      Fail(name + " has sparse indices of a type the spec does not allow");
    const unsigned char* indices =
        ViewBytes(gltf_, file_, a.sparse.indices.bufferView, size_t(std::max(a.sparse.indices.byteOffset, 0)), count,
                  indexBytes, indexBytes, name + "'s sparse indices");
    const unsigned char* substitutes =
        ViewBytes(gltf_, file_, a.sparse.values.bufferView, size_t(std::max(a.sparse.values.byteOffset, 0)), count,
                  elementBytes, elementBytes, name + "'s sparse values");
    for (size_t i = 0; i < count; ++i) {
      const double at = ReadComponent(indices + i * indexBytes, indexType, false);
      if (!(at < double(a.count))) Fail(name + " has a sparse index out of range");
      for (int c = 0; c < components; ++c)
        values[size_t(at) * size_t(components) + size_t(c)] =
            ReadComponent(substitutes + i * elementBytes + size_t(c) * bytes, a.componentType, a.normalized);
    }
  }
  for (float v : values)
    if (!std::isfinite(v)) Fail(name + " holds a non-finite value (NaN or infinity)");
  return values;
}

std::vector<uint32_t> Loader::ReadIndices(int index, size_t vertexCount, const std::string& what) const {
  int components = 0;
  if (index >= 0 && size_t(index) < gltf_.accessors.size()) {
    const int type = gltf_.accessors[size_t(index)].componentType;
    if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      Fail(what + " (accessor " + std::to_string(index) + ") must hold unsigned integers");
  }
  const std::vector<float> values = ReadAccessor(index, what, {TINYGLTF_TYPE_SCALAR}, components);
  // Unsigned ints above 2^24 are not exact in float: read them again as integers.
  const tinygltf::Accessor& a = gltf_.accessors[size_t(index)];
  std::vector<uint32_t> indices(values.size());
  if (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT && a.bufferView >= 0 && !a.sparse.isSparse) {
    const size_t viewStride = gltf_.bufferViews[size_t(a.bufferView)].byteStride;
    const size_t stride = viewStride != 0 ? viewStride : 4;
    const unsigned char* data = ViewBytes(gltf_, file_, a.bufferView, a.byteOffset, a.count, 4, stride, what);
    for (size_t i = 0; i < a.count; ++i) std::memcpy(&indices[i], data + i * stride, 4);
  } else {
    for (size_t i = 0; i < values.size(); ++i) indices[i] = uint32_t(values[i]);
  }
  for (uint32_t i : indices)
    if (i >= vertexCount)
      Fail(what + " (accessor " + std::to_string(index) + ") holds index " + std::to_string(i) + ", beyond the " +
           std::to_string(vertexCount) + " vertices");
  return indices;
}

glm::dmat4 LocalTransform(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) {
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = node.matrix[size_t(c * 4 + r)];
    return m;
  }
  glm::dmat4 m(1.0);
  if (node.translation.size() == 3)
    m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4)  // glTF: x, y, z, w; glm's constructor: w, x, y, z
    m = m * glm::mat4_cast(
                glm::normalize(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2])));
  if (node.scale.size() == 3) m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  return m;
}

bool Finite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

void Loader::VisitNode(int index, const glm::dmat4& parent, std::vector<int>& path) {
  if (index < 0 || size_t(index) >= gltf_.nodes.size())
    Fail("names node " + std::to_string(index) + ", which does not exist");
  if (std::find(path.begin(), path.end(), index) != path.end())
    Fail("node " + std::to_string(index) + " is its own ancestor (the node hierarchy has a cycle)");
  const tinygltf::Node& node = gltf_.nodes[size_t(index)];
  const glm::dmat4 transform = parent * LocalTransform(node);
  if (!Finite(transform)) Fail("node " + std::to_string(index) + "'s transform is not finite");
  const std::string what = "node " + std::to_string(index);
  if (node.mesh >= 0) {
    if (size_t(node.mesh) >= gltf_.meshes.size())
      Fail(what + " names mesh " + std::to_string(node.mesh) + ", which does not exist");
    const tinygltf::Mesh& mesh = gltf_.meshes[size_t(node.mesh)];
    if (node.skin >= 0) Warn("skinned meshes are drawn in their bind pose, without the skin's joints");
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      if (!mesh.primitives[p].targets.empty()) Warn("morph targets are drawn in the bind pose (no target applied)");
      AddPrimitive(mesh.primitives[p], transform,
                   "mesh " + std::to_string(node.mesh) + " primitive " + std::to_string(p));
    }
  }
  if (node.camera >= 0) AddCamera(node.camera, transform);
  if (const auto ext = node.extensions.find("KHR_lights_punctual"); ext != node.extensions.end()) {
    if (!ext->second.IsObject() || !ext->second.Get("light").IsNumber())
      Fail(what + "'s KHR_lights_punctual must name a light");
    AddLight(ext->second.Get("light").GetNumberAsInt(), transform);
  }
  path.push_back(index);
  for (int child : node.children) VisitNode(child, transform, path);
  path.pop_back();
}

// A texture's KHR_texture_transform as the 3x3 matrix T R S of the extension's spec, and its
// texCoord override.
struct UvTransform {
  int texCoord = 0;
  glm::dmat3 matrix{1.0};
  bool operator==(const UvTransform& o) const { return texCoord == o.texCoord && matrix == o.matrix; }
};

UvTransform UvTransformOf(const tinygltf::ExtensionMap& extensions, int texCoord) {
  UvTransform t;
  t.texCoord = texCoord;
  const auto ext = extensions.find("KHR_texture_transform");
  if (ext == extensions.end() || !ext->second.IsObject()) return t;
  const tinygltf::Value& v = ext->second;
  const auto number = [](const tinygltf::Value& value, size_t i, double fallback) {
    return value.IsArray() && value.ArrayLen() > i && value.Get(int(i)).IsNumber()
               ? value.Get(int(i)).GetNumberAsDouble()
               : fallback;
  };
  const double ox = number(v.Get("offset"), 0, 0.0), oy = number(v.Get("offset"), 1, 0.0);
  const double sx = number(v.Get("scale"), 0, 1.0), sy = number(v.Get("scale"), 1, 1.0);
  const double rotation = v.Get("rotation").IsNumber() ? v.Get("rotation").GetNumberAsDouble() : 0.0;
  if (v.Get("texCoord").IsNumber()) t.texCoord = v.Get("texCoord").GetNumberAsInt();
  // Column-major: translation * rotation * scale (KHR_texture_transform's reference shader).
  const glm::dmat3 translation(1, 0, 0, 0, 1, 0, ox, oy, 1);
  const glm::dmat3 rotate(std::cos(rotation), -std::sin(rotation), 0, std::sin(rotation), std::cos(rotation), 0, 0, 0,
                          1);
  const glm::dmat3 scale(sx, 0, 0, 0, sy, 0, 0, 0, 1);
  t.matrix = translation * rotate * scale;
  return t;
}

int32_t Loader::TextureFor(int textureIndex, int role, const std::string& what) {
  if (textureIndex < 0) return kNoTexture;
  if (size_t(textureIndex) >= gltf_.textures.size())
    Fail(what + " names texture " + std::to_string(textureIndex) + ", which does not exist");
  const tinygltf::Texture& texture = gltf_.textures[size_t(textureIndex)];
  if (texture.source < 0 || size_t(texture.source) >= gltf_.images.size())
    Fail("texture " + std::to_string(textureIndex) + " has no image ssgi can read (KTX2 and WebP are not supported)");
  TextureWrap wrapU = TextureWrap::kRepeat, wrapV = TextureWrap::kRepeat;
  if (texture.sampler >= 0) {
    if (size_t(texture.sampler) >= gltf_.samplers.size())
      Fail("texture " + std::to_string(textureIndex) + " names a sampler that does not exist");
    const tinygltf::Sampler& s = gltf_.samplers[size_t(texture.sampler)];
    const auto wrap = [&](int mode) {
      if (mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return TextureWrap::kClamp;
      if (mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return TextureWrap::kMirror;
      if (mode != TINYGLTF_TEXTURE_WRAP_REPEAT)
        Fail("sampler " + std::to_string(texture.sampler) + " has an unknown wrap mode " + std::to_string(mode));
      return TextureWrap::kRepeat;
    };
    wrapU = wrap(s.wrapS);
    wrapV = wrap(s.wrapT);
    if ((s.magFilter != -1 && s.magFilter != TINYGLTF_TEXTURE_FILTER_LINEAR) ||
        (s.minFilter != -1 && s.minFilter != TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR))
      Warn("texture samplers' filters other than LINEAR / LINEAR_MIPMAP_LINEAR are sampled trilinearly");
  }
  const auto [it, inserted] = textures_.emplace(TextureKey{texture.source, role, wrapU, wrapV}, 0);
  if (!inserted) return it->second;
  const tinygltf::Image& image = gltf_.images[size_t(texture.source)];
  if (image.image.empty())
    Fail("image " + std::to_string(texture.source) + (image.uri.empty() ? "" : " (" + image.uri + ")") +
         " is missing or not a PNG, JPEG, BMP or other format stb_image decodes");
  const int channels = image.component;
  if (image.width <= 0 || image.height <= 0 || channels < 1 || channels > 4 || (image.bits != 8 && image.bits != 16) ||
      image.image.size() != size_t(image.width) * size_t(image.height) * size_t(channels) * size_t(image.bits / 8))
    Fail("image " + std::to_string(texture.source) + " could not be decoded");
  if (image.width > kMaxTextureSide || image.height > kMaxTextureSide)
    Fail("image " + std::to_string(texture.source) + " is larger than " + std::to_string(kMaxTextureSide) +
         " texels on a side");
  const size_t texels = size_t(image.width) * size_t(image.height);
  const auto code = [&](size_t texel, int channel) -> uint8_t {
    const size_t at = texel * size_t(channels) + size_t(channel);
    if (image.bits == 8) return image.image[at];
    uint16_t v;
    std::memcpy(&v, &image.image[2 * at], 2);  // stb_image gives native order
    return uint8_t((uint32_t(v) * 255u + 32767u) / 65535u);
  };
  // Grey and grey+alpha images: their first channel is R, G and B.
  const auto channel = [&](size_t texel, int c) -> uint8_t {
    if (channels <= 2) return c == 3 ? (channels == 2 ? code(texel, 1) : 255) : code(texel, 0);
    return c < channels ? code(texel, c) : 255;
  };
  std::vector<uint8_t> rgba(4 * texels);
  for (size_t t = 0; t < texels; ++t) {
    for (int c = 0; c < 4; ++c) {
      // metallicRoughnessTexture: metallic in B, roughness in G, read by the resolve from R.
      const int from = role == kMetallicRole ? (c == 3 ? 3 : 2) : role == kRoughnessRole ? (c == 3 ? 3 : 1) : c;
      rgba[4 * t + size_t(c)] = channel(t, from);
    }
  }
  Texture made = MakeTexture(image.width, image.height, std::move(rgba),
                             role == kBaseColorRole ? TextureEncoding::kSrgb : TextureEncoding::kLinear);
  made.sourceChannels = role == kBaseColorRole ? channels : 3;
  made.wrapU = wrapU;
  made.wrapV = wrapV;
  it->second = int32_t(out_.textures.size());
  out_.textures.push_back(std::move(made));
  return it->second;
}

uint32_t Loader::MaterialFor(int index, bool vertexColors, bool& invisible) {
  const auto key = std::make_pair(index, vertexColors);
  if (const auto it = materials_.find(key); it != materials_.end()) {
    invisible = invisibleMaterials_[key];
    return it->second;
  }
  Material m;
  invisible = false;
  if (index >= 0 && size_t(index) >= gltf_.materials.size())
    Fail("a primitive names material " + std::to_string(index) + ", which does not exist");
  // The spec's default material: white, fully metallic and rough.
  const tinygltf::Material fallback;
  const tinygltf::Material& g = index >= 0 ? gltf_.materials[size_t(index)] : fallback;
  const std::string what = "material " + std::to_string(index);
  m.name = g.name.empty() ? (index >= 0 ? what : "(default)") : g.name;
  const tinygltf::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
  if (pbr.baseColorFactor.size() != 4) Fail(what + "'s baseColorFactor must have 4 numbers");
  for (double f : pbr.baseColorFactor)
    if (!(f >= 0.0 && f <= 1.0)) Fail(what + "'s baseColorFactor must be in [0, 1]");
  if (!(pbr.metallicFactor >= 0.0 && pbr.metallicFactor <= 1.0) ||
      !(pbr.roughnessFactor >= 0.0 && pbr.roughnessFactor <= 1.0))
    Fail(what + "'s metallicFactor and roughnessFactor must be in [0, 1]");
  m.baseColor = glm::vec3(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]), float(pbr.baseColorFactor[2]));
  m.metallic = float(pbr.metallicFactor);
  m.roughness = float(pbr.roughnessFactor);
  m.baseColorTexture = TextureFor(pbr.baseColorTexture.index, kBaseColorRole, what);
  m.metallicTexture = TextureFor(pbr.metallicRoughnessTexture.index, kMetallicRole, what);
  m.roughnessTexture = TextureFor(pbr.metallicRoughnessTexture.index, kRoughnessRole, what);
  m.normalTexture = TextureFor(g.normalTexture.index, kNormalRole, what);
  m.normalScale = float(g.normalTexture.scale);
  if (!std::isfinite(m.normalScale)) Fail(what + "'s normalTexture.scale is not finite");
  m.twoSided = g.doubleSided;
  m.vertexColors = vertexColors;
  if (m.normalTexture != kNoTexture) normalMapped_ = true;
  if (g.occlusionTexture.index >= 0)
    Warn(
        "occlusionTexture is not used: the G-buffer has no slot for it (the diffuse bounce's ambient occlusion "
        "darkens the sky light instead)");
  if (g.emissiveTexture.index >= 0 ||
      (g.emissiveFactor.size() == 3 && (g.emissiveFactor[0] > 0 || g.emissiveFactor[1] > 0 || g.emissiveFactor[2] > 0)))
    Warn("emission is not rendered: the G-buffer has no slot for it");
  for (const auto& [name, value] : g.extensions)
    if (!kSupportedExtensions.count(name)) Warn(name + " is ignored: ssgi's materials are metallic-roughness only");
  const float alpha = float(pbr.baseColorFactor[3]);
  if (g.alphaMode == "MASK" || g.alphaMode == "BLEND") {
    float cutoff = float(g.alphaCutoff);
    if (g.alphaMode == "BLEND") {
      Warn("alphaMode BLEND is drawn as MASK with alphaCutoff 0.5");
      cutoff = 0.5f;
    }
    // alpha = factor * texture >= cutoff  <=>  texture >= cutoff / factor.
    const bool textureAlpha =
        m.baseColorTexture != kNoTexture && (out_.textures[size_t(m.baseColorTexture)].sourceChannels == 2 ||
                                             out_.textures[size_t(m.baseColorTexture)].sourceChannels == 4);
    if (textureAlpha && alpha > 0.0f) {
      m.alphaTexture = m.baseColorTexture;
      m.alphaCutoff = cutoff / alpha;
    } else {
      invisible = alpha < cutoff;
    }
  } else if (!g.alphaMode.empty() && g.alphaMode != "OPAQUE") {
    Fail(what + " has alphaMode " + g.alphaMode + " (OPAQUE, MASK or BLEND)");
  }
  const uint32_t added = uint32_t(out_.materials.size());
  out_.materials.push_back(std::move(m));
  materials_.emplace(key, added);
  invisibleMaterials_[key] = invisible;
  return added;
}

void Loader::AddPrimitive(const tinygltf::Primitive& primitive, const glm::dmat4& transform, const std::string& what) {
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  if (mode < TINYGLTF_MODE_TRIANGLES || mode > TINYGLTF_MODE_TRIANGLE_FAN)
    Fail(what + " draws points or lines (mode " + std::to_string(mode) + "): only triangles are supported");
  if (primitive.extensions.count("KHR_draco_mesh_compression") &&
      (!primitive.attributes.count("POSITION") || primitive.attributes.at("POSITION") < 0 ||
       gltf_.accessors.size() <= size_t(primitive.attributes.at("POSITION")) ||
       gltf_.accessors[size_t(primitive.attributes.at("POSITION"))].bufferView < 0))
    Fail(what + ": " + kDracoRefusal);
  const auto attribute = [&](const std::string& name) {
    const auto it = primitive.attributes.find(name);
    return it == primitive.attributes.end() ? -1 : it->second;
  };
  if (attribute("POSITION") < 0) Fail(what + " has no POSITION");
  int components = 0;
  const std::vector<float> positions =
      ReadAccessor(attribute("POSITION"), what + " POSITION", {TINYGLTF_TYPE_VEC3}, components);
  const size_t vertexCount = positions.size() / 3;
  const auto checkCount = [&](const std::vector<float>& values, int n, const std::string& name) {
    if (values.size() != vertexCount * size_t(n)) Fail(what + " " + name + " has another count than POSITION");
  };
  std::vector<float> normals, tangents, colors, uvs;
  if (attribute("NORMAL") >= 0) {
    normals = ReadAccessor(attribute("NORMAL"), what + " NORMAL", {TINYGLTF_TYPE_VEC3}, components);
    checkCount(normals, 3, "NORMAL");
  }
  int colorComponents = 0;
  if (attribute("COLOR_0") >= 0) {
    colors = ReadAccessor(attribute("COLOR_0"), what + " COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4},
                          colorComponents);
    checkCount(colors, colorComponents, "COLOR_0");
  }
  bool invisible = false;
  const uint32_t material = MaterialFor(primitive.material, !colors.empty(), invisible);
  if (invisible) return;  // a constant alpha below the cut-off
  const Material& m = out_.materials[material];
  // The UV set and transform: the base colour texture's, else the metallic-roughness one's, else
  // the normal texture's (one set per vertex in ssgi's mesh).
  std::vector<UvTransform> used;
  if (primitive.material >= 0) {
    const tinygltf::Material& g = gltf_.materials[size_t(primitive.material)];
    const tinygltf::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
    if (pbr.baseColorTexture.index >= 0)
      used.push_back(UvTransformOf(pbr.baseColorTexture.extensions, pbr.baseColorTexture.texCoord));
    if (pbr.metallicRoughnessTexture.index >= 0)
      used.push_back(UvTransformOf(pbr.metallicRoughnessTexture.extensions, pbr.metallicRoughnessTexture.texCoord));
    if (g.normalTexture.index >= 0) used.push_back(UvTransformOf(g.normalTexture.extensions, g.normalTexture.texCoord));
  }
  const UvTransform uvTransform = used.empty() ? UvTransform{} : used.front();
  if (std::any_of(used.begin(), used.end(), [&](const UvTransform& t) { return !(t == uvTransform); }))
    Warn("a material's textures use different UV sets or transforms: all use its first texture's");
  const int uvAttribute = attribute("TEXCOORD_" + std::to_string(uvTransform.texCoord));
  if (!used.empty() && uvAttribute < 0)
    Fail(what + " has no TEXCOORD_" + std::to_string(uvTransform.texCoord) + " for its material's textures");
  if (uvAttribute >= 0) {
    uvs = ReadAccessor(uvAttribute, what + " TEXCOORD_" + std::to_string(uvTransform.texCoord), {TINYGLTF_TYPE_VEC2},
                       components);
    checkCount(uvs, 2, "TEXCOORD");
  }
  if (m.normalTexture != kNoTexture && attribute("TANGENT") >= 0 && !normals.empty()) {
    tangents = ReadAccessor(attribute("TANGENT"), what + " TANGENT", {TINYGLTF_TYPE_VEC4}, components);
    checkCount(tangents, 4, "TANGENT");
  }

  // The corners of the triangles, by the mode's rule (glTF 2.0 §3.7.2.1).
  std::vector<uint32_t> order;
  if (primitive.indices >= 0) {
    order = ReadIndices(primitive.indices, vertexCount, what + " indices");
  } else {
    order.resize(vertexCount);
    for (size_t i = 0; i < vertexCount; ++i) order[i] = uint32_t(i);
  }
  std::vector<uint32_t> corners;
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    corners.assign(order.begin(), order.begin() + std::ptrdiff_t(order.size() / 3 * 3));
  } else {
    for (size_t i = 0; i + 2 < order.size(); ++i) {
      if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        corners.insert(corners.end(), {order[i], order[i + 1 + i % 2], order[i + 2 - i % 2]});
      } else {
        corners.insert(corners.end(), {order[i + 1], order[i + 2], order[0]});
      }
    }
  }
  if (corners.empty()) return;

  Mesh& mesh = out_.mesh;
  const glm::dmat3 linear(transform);
  const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(linear));
  const bool mirrored = glm::determinant(linear) < 0.0;
  const auto position = [&](uint32_t v) {
    return glm::vec3(transform * glm::dvec4(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2], 1.0));
  };
  const auto uvOf = [&](uint32_t v) {
    if (uvs.empty()) return glm::vec2(0.0f);
    const glm::dvec3 t = uvTransform.matrix * glm::dvec3(uvs[2 * v], uvs[2 * v + 1], 1.0);
    return glm::vec2(float(t.x), float(1.0 - t.y));  // glTF's v runs down the image, ssgi's up
  };
  const auto colorOf = [&](uint32_t v) {
    const float* c = &colors[size_t(colorComponents) * v];
    return glm::vec3(c[0], c[1], c[2]);
  };
  const size_t first = mesh.positions.size();
  const size_t triangles = corners.size() / 3;
  if (!colors.empty()) mesh.colors.resize(first, glm::vec3(1.0f));
  if (first + (normals.empty() ? corners.size() : vertexCount) > std::numeric_limits<uint32_t>::max())
    Fail("the model has more than 2^32 - 1 vertices");
  if (normals.empty()) {
    // No normals: flat shading (glTF 2.0 §3.7.2.1), one vertex per corner with its face's normal.
    for (size_t t = 0; t < triangles; ++t) {
      const uint32_t* c = &corners[3 * t];
      const glm::vec3 p0 = position(c[0]), p1 = position(c[1]), p2 = position(c[2]);
      glm::vec3 n = glm::cross(p1 - p0, p2 - p0) * (mirrored ? -1.0f : 1.0f);
      n = glm::dot(n, n) > 0.0f ? glm::normalize(n) : glm::vec3(0.0f, 0.0f, 1.0f);
      for (int k = 0; k < 3; ++k) {
        mesh.positions.push_back(position(c[k]));
        mesh.normals.push_back(n);
        mesh.uvs.push_back(uvOf(c[k]));
        if (!colors.empty()) mesh.colors.push_back(colorOf(c[k]));
      }
      corners[3 * t] = uint32_t(3 * t), corners[3 * t + 1] = uint32_t(3 * t + 1),
                  corners[3 * t + 2] = uint32_t(3 * t + 2);
    }
  } else {
    for (uint32_t v = 0; v < vertexCount; ++v) {
      mesh.positions.push_back(position(v));
      glm::vec3 n(normalMatrix * glm::dvec3(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]));
      // A zero normal is left zero: the resolve then shades with the face's.
      if (glm::dot(n, n) > 0.0f) n = glm::normalize(n);
      mesh.normals.push_back(n);
      mesh.uvs.push_back(uvOf(v));
      if (!colors.empty()) mesh.colors.push_back(colorOf(v));
      if (!tangents.empty()) {
        glm::vec3 t(linear * glm::dvec3(tangents[4 * v], tangents[4 * v + 1], tangents[4 * v + 2]));
        if (glm::dot(t, t) > 0.0f) t = glm::normalize(t);
        const float sign = (tangents[4 * v + 3] < 0.0f ? -1.0f : 1.0f) * (mirrored ? -1.0f : 1.0f);
        mesh.tangents.resize(first + v, glm::vec4(0.0f));
        mesh.tangents.push_back(glm::vec4(t, sign));
      }
    }
  }
  for (const glm::vec3& p : mesh.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      Fail(what + ": the node transforms make a position non-finite");
  // Every vertex array but tangents (filled later) and colours (when any primitive has them) is per
  // position; colours of primitives without COLOR_0 are white.
  if (!mesh.colors.empty() || !colors.empty()) mesh.colors.resize(mesh.positions.size(), glm::vec3(1.0f));
  for (size_t t = 0; t < triangles; ++t) {
    const uint32_t* c = &corners[3 * t];
    // A mirroring transform turns counter-clockwise triangles clockwise: swap two corners back.
    mesh.indices.push_back(uint32_t(first) + c[0]);
    mesh.indices.push_back(uint32_t(first) + c[mirrored ? 2 : 1]);
    mesh.indices.push_back(uint32_t(first) + c[mirrored ? 1 : 2]);
    mesh.materials.push_back(material);
  }
  // Tangents from the file are kept; the others are generated once the whole mesh is in.
  if (!tangents.empty()) mesh.tangents.resize(mesh.positions.size(), glm::vec4(0.0f));
}

void Loader::AddLight(int index, const glm::dmat4& transform) {
  const auto lights = gltf_.extensions.find("KHR_lights_punctual");
  if (index < 0 || size_t(index) >= gltf_.lights.size())
    Fail("a node names light " + std::to_string(index) + ", which does not exist" +
         (lights == gltf_.extensions.end() ? " (the file has no KHR_lights_punctual lights)" : ""));
  const tinygltf::Light& l = gltf_.lights[size_t(index)];
  const std::string what = "light " + std::to_string(index);
  glm::vec3 color(1.0f);
  if (!l.color.empty()) {
    if (l.color.size() != 3) Fail(what + "'s color must have 3 numbers");
    color = glm::vec3(float(l.color[0]), float(l.color[1]), float(l.color[2]));
  }
  if (!(l.intensity >= 0.0) || !std::isfinite(l.intensity) || !(color.x >= 0 && color.y >= 0 && color.z >= 0))
    Fail(what + " has a negative or non-finite intensity or colour");
  if (l.range > 0.0) Warn("lights' range is ignored: ssgi's lights fall off with the inverse square to any distance");
  const glm::vec3 power = color * float(l.intensity / double(kLumensPerWatt));
  const glm::dvec3 axis = glm::dmat3(transform) * glm::dvec3(0.0, 0.0, -1.0);
  const glm::vec3 position(transform * glm::dvec4(0.0, 0.0, 0.0, 1.0));
  if (l.type == "directional" || l.type == "spot") {
    if (!(glm::length(axis) > 0.0)) Fail(what + "'s node transform has no direction");
  }
  if (l.type == "directional") {
    DirectionalLight d;
    d.direction = glm::vec3(glm::normalize(axis));
    d.irradiance = power;
    d.angularDiameterDegrees = 0.0f;
    out_.directionalLights.push_back(d);
  } else if (l.type == "spot") {
    SpotLight s;
    s.position = position;
    s.direction = glm::vec3(glm::normalize(axis));
    s.radius = 0.0f;
    s.intensity = power;
    // Half-angles; ssgi's cone must stay below 90 degrees (its shadow map is a perspective view).
    const double inner = glm::degrees(l.spot.innerConeAngle), outer = glm::degrees(l.spot.outerConeAngle);
    if (!(inner >= 0.0) || !(outer > 0.0) || !(inner < outer) || !(outer <= 90.0))
      Fail(what + "'s cone angles must satisfy 0 <= innerConeAngle < outerConeAngle <= pi/2");
    s.outerConeDegrees = float(std::min(outer, 89.0));
    s.innerConeDegrees = float(std::min(inner, double(s.outerConeDegrees)));
    out_.spotLights.push_back(s);
  } else if (l.type == "point") {
    PointLight p;
    p.position = position;
    p.radius = 0.0f;
    p.intensity = power;
    out_.pointLights.push_back(p);
  } else {
    Fail(what + " has type '" + l.type + "' (directional, spot or point)");
  }
}

void Loader::AddCamera(int index, const glm::dmat4& transform) {
  if (size_t(index) >= gltf_.cameras.size())
    Fail("a node names camera " + std::to_string(index) + ", which does not exist");
  const tinygltf::Camera& c = gltf_.cameras[size_t(index)];
  const std::string what = "camera " + std::to_string(index);
  const glm::dvec3 eye(transform * glm::dvec4(0.0, 0.0, 0.0, 1.0));
  const glm::dvec3 forward = glm::dmat3(transform) * glm::dvec3(0.0, 0.0, -1.0);
  const glm::dvec3 up = glm::dmat3(transform) * glm::dvec3(0.0, 1.0, 0.0);
  if (!(glm::length(glm::cross(forward, up)) > 0.0)) Fail(what + "'s node transform is degenerate");
  GltfCamera camera;
  camera.desc.position = glm::vec3(eye);
  camera.desc.up = glm::vec3(glm::normalize(up));
  if (c.type == "perspective") {
    const tinygltf::PerspectiveCamera& p = c.perspective;
    if (!(p.yfov > 0.0 && p.yfov < glm::pi<double>()) || !(p.znear > 0.0) || !(p.aspectRatio >= 0.0))
      Fail(what + " needs 0 < yfov < pi, znear > 0 and aspectRatio > 0");
    camera.desc.target = glm::vec3(eye + glm::normalize(forward));
    camera.desc.fovYDegrees = float(glm::degrees(p.yfov));
    camera.desc.nearPlane = float(p.znear);
    camera.aspectRatio = float(p.aspectRatio);
  } else if (c.type == "orthographic") {
    const tinygltf::OrthographicCamera& o = c.orthographic;
    if (!(o.xmag != 0.0) || !(o.ymag != 0.0) || !(o.znear >= 0.0) || !(o.zfar > o.znear) || !std::isfinite(o.xmag) ||
        !std::isfinite(o.ymag) || !std::isfinite(o.zfar))
      Fail(what + " needs non-zero xmag and ymag and 0 <= znear < zfar");
    // The frame's passes are perspective (screen-space rays from the eye): an orthographic camera is
    // drawn from kOrthographicDistance view heights behind its plane with the field of view that
    // keeps ymag at the middle of its depth range; the distortion across [znear, zfar] is
    // (zfar - znear) / (2 distance).
    constexpr double kOrthographicDistance = 1000.0;
    const double ymag = std::fabs(o.ymag), xmag = std::fabs(o.xmag);
    const double back = kOrthographicDistance * 2.0 * std::max(xmag, ymag);
    const glm::dvec3 axis = glm::normalize(forward);
    const double middle = back + 0.5 * (o.znear + o.zfar);
    camera.desc.position = glm::vec3(eye - axis * back);
    camera.desc.target = glm::vec3(eye);
    camera.desc.fovYDegrees = float(glm::degrees(2.0 * std::atan(ymag / middle)));
    camera.desc.nearPlane = float(back + o.znear);
    camera.aspectRatio = float(xmag / ymag);
    Warn("orthographic cameras are drawn as a narrow perspective from far behind (ssgi's passes are perspective)");
  } else {
    Fail(what + " has type '" + c.type + "' (perspective or orthographic)");
  }
  out_.cameras.push_back(camera);
}

GltfModel Loader::Load() {
  CheckExtensions();
  if (!gltf_.skins.empty() && gltf_.nodes.empty()) Warn("skins are ignored");
  std::vector<int> roots;
  if (!gltf_.scenes.empty()) {
    const int scene = gltf_.defaultScene >= 0 ? gltf_.defaultScene : 0;
    if (size_t(scene) >= gltf_.scenes.size()) Fail("its scene " + std::to_string(scene) + " does not exist");
    roots = gltf_.scenes[size_t(scene)].nodes;
  } else {
    // No scene: every node that is no other's child (glTF 2.0 leaves this to the application).
    std::vector<bool> child(gltf_.nodes.size(), false);
    for (const tinygltf::Node& node : gltf_.nodes)
      for (int c : node.children)
        if (c >= 0 && size_t(c) < child.size()) child[size_t(c)] = true;
    for (size_t n = 0; n < gltf_.nodes.size(); ++n)
      if (!child[n]) roots.push_back(int(n));
  }
  std::vector<int> path;
  for (int root : roots) VisitNode(root, glm::dmat4(1.0), path);
  if (out_.mesh.TriangleCount() == 0) Fail("has no triangles to draw");
  if (normalMapped_) {
    // Tangents for the vertices the file gives none: generated over the whole mesh; the file's are
    // kept where it has them.
    std::vector<glm::vec4> given = std::move(out_.mesh.tangents);
    given.resize(out_.mesh.positions.size(), glm::vec4(0.0f));
    GenerateTangents(out_.mesh);
    for (size_t v = 0; v < given.size(); ++v)
      if (given[v] != glm::vec4(0.0f)) out_.mesh.tangents[v] = given[v];
  } else {
    out_.mesh.tangents.clear();
  }
  return std::move(out_);
}

// Bits of a vertex's position, normal and UV, the key MikkTSpace welds corners by.
struct VertexKey {
  std::array<uint32_t, 8> bits;
  bool operator==(const VertexKey& o) const { return bits == o.bits; }
};
struct VertexKeyHash {
  size_t operator()(const VertexKey& k) const {
    size_t h = 0;
    for (uint32_t b : k.bits) h = h * 1000003u ^ b;
    return h;
  }
};

}  // namespace

void GenerateTangents(Mesh& mesh) {
  const size_t vertices = mesh.positions.size();
  const size_t triangles = mesh.TriangleCount();
  std::unordered_map<VertexKey, uint32_t, VertexKeyHash> groups;
  std::vector<uint32_t> groupOf(vertices);
  for (size_t v = 0; v < vertices; ++v) {
    VertexKey key;
    std::memcpy(&key.bits[0], &mesh.positions[v], 12);
    std::memcpy(&key.bits[3], &mesh.normals[v], 12);
    std::memcpy(&key.bits[6], &mesh.uvs[v], 8);
    groupOf[v] = groups.emplace(key, uint32_t(groups.size())).first->second;
  }
  // Per (group, orientation): the angle-weighted sum of the corners' projected tangents.
  std::vector<glm::dvec3> sum(2 * groups.size(), glm::dvec3(0.0));
  std::vector<int8_t> orientation(triangles, 1);
  for (size_t t = 0; t < triangles; ++t) {
    const uint32_t* c = &mesh.indices[3 * t];
    const glm::dvec3 p0 = mesh.positions[c[0]], p1 = mesh.positions[c[1]], p2 = mesh.positions[c[2]];
    const glm::dvec2 t0 = mesh.uvs[c[0]], t1 = mesh.uvs[c[1]], t2 = mesh.uvs[c[2]];
    const glm::dvec3 d1 = p1 - p0, d2 = p2 - p0;
    const glm::dvec2 s1 = t1 - t0, s2 = t2 - t0;
    const double area = s1.x * s2.y - s1.y * s2.x;  // signed, twice the UV triangle's
    orientation[t] = area > 0.0 ? 1 : -1;
    // The direction of increasing u on the triangle: (s2.y d1 - s1.y d2) / area.
    glm::dvec3 os = s2.y * d1 - s1.y * d2;
    if (!(area != 0.0) || !(glm::length(os) > 0.0)) continue;
    os = glm::normalize(os) * (area > 0.0 ? 1.0 : -1.0);
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 n = mesh.normals[c[k]];
      const glm::dvec3 here = mesh.positions[c[k]];
      glm::dvec3 a = glm::dvec3(mesh.positions[c[(k + 1) % 3]]) - here;
      glm::dvec3 b = glm::dvec3(mesh.positions[c[(k + 2) % 3]]) - here;
      a -= n * glm::dot(n, a);
      b -= n * glm::dot(n, b);
      glm::dvec3 projected = os - n * glm::dot(n, os);
      if (!(glm::length(a) > 0.0) || !(glm::length(b) > 0.0) || !(glm::length(projected) > 0.0)) continue;
      const double angle = std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0));
      sum[2 * groupOf[c[k]] + (area > 0.0 ? 0 : 1)] += glm::normalize(projected) * angle;
    }
  }
  // A vertex used by triangles of both orientations is split: the negative ones get a copy.
  std::vector<uint32_t> negativeCopy(vertices, UINT32_MAX);
  std::vector<int> positiveUse(vertices, 0), negativeUse(vertices, 0);
  for (size_t t = 0; t < triangles; ++t)
    for (int k = 0; k < 3; ++k) (orientation[t] > 0 ? positiveUse : negativeUse)[mesh.indices[3 * t + k]]++;
  for (size_t t = 0; t < triangles; ++t) {
    if (orientation[t] > 0) continue;
    for (int k = 0; k < 3; ++k) {
      uint32_t& corner = mesh.indices[3 * t + size_t(k)];
      if (positiveUse[corner] == 0) continue;
      if (negativeCopy[corner] == UINT32_MAX) {
        negativeCopy[corner] = uint32_t(mesh.positions.size());
        mesh.positions.push_back(mesh.positions[corner]);
        mesh.normals.push_back(mesh.normals[corner]);
        mesh.uvs.push_back(mesh.uvs[corner]);
        if (!mesh.colors.empty()) mesh.colors.push_back(mesh.colors[corner]);
        groupOf.push_back(groupOf[corner]);
        negativeUse.push_back(1);
        positiveUse.push_back(0);
      }
      corner = negativeCopy[corner];
    }
  }
  mesh.tangents.assign(mesh.positions.size(), glm::vec4(0.0f));
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const bool negative = negativeUse[v] > 0 && positiveUse[v] == 0;
    const glm::dvec3 n = mesh.normals[v];
    glm::dvec3 t = sum[2 * groupOf[v] + (negative ? 1 : 0)];
    t -= n * glm::dot(n, t);
    if (!(glm::length(t) > 1e-20)) {
      // No usable UV gradient: any tangent orthogonal to the normal.
      const glm::dvec3 axis = std::fabs(n.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
      t = axis - n * glm::dot(n, axis);
      if (!(glm::length(t) > 0.0)) t = glm::dvec3(1.0, 0.0, 0.0);
    }
    mesh.tangents[v] = glm::vec4(glm::vec3(glm::normalize(t)), negative ? -1.0f : 1.0f);
  }
}

GltfModel LoadGltfModel(const fs::path& file) {
  std::error_code error;
  if (!fs::is_regular_file(file, error)) throw InputError(file, "glTF file not found");
  tinygltf::TinyGLTF parser;
  parser.SetPreserveImageChannels(true);
  tinygltf::Model model;
  std::string problem, warning;
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  bool loaded = false;
  try {
    loaded = ext == ".glb" ? parser.LoadBinaryFromFile(&model, &problem, &warning, file.string())
                           : parser.LoadASCIIFromFile(&model, &problem, &warning, file.string());
  } catch (const std::exception& e) {
    throw InputError(file, OneLine(e.what()));
  }
  if (!loaded) {
    // tinygltf fails on a Draco mesh's accessors before the extension can be named: say why.
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.find("\"KHR_draco_mesh_compression\"") != std::string::npos) throw InputError(file, kDracoRefusal);
    throw InputError(file, OneLine(problem.empty() ? warning : problem));
  }
  if (model.asset.version.rfind("2.", 0) != 0) throw InputError(file, "is glTF " + model.asset.version + ", not 2.0");
  return Loader(file, model).Load();
}

}  // namespace ssgi
