#include "core/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <iterator>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include "core/check.h"
#include "core/error.h"
#include "core/gltf_loader.h"
#include "core/obj_loader.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

std::string LowerExtension(const fs::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// A character iterator that records the furthest position the JSON parser has read, so the parser
// callback knows the line of each key and value (nlohmann reports positions for syntax errors only).
class TrackingIterator {
 public:
  using iterator_category = std::forward_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  TrackingIterator(const char* at, const char** furthest) : at_(at), furthest_(furthest) {}
  reference operator*() const { return *at_; }
  TrackingIterator& operator++() {
    *furthest_ = std::max(*furthest_, ++at_);
    return *this;
  }
  TrackingIterator operator++(int) {
    TrackingIterator before = *this;
    ++*this;
    return before;
  }
  bool operator==(const TrackingIterator& other) const { return at_ == other.at_; }

 private:
  const char* at_;
  const char** furthest_;
};

// The 1-based line of the character at `offset`.
int LineAt(std::string_view text, size_t offset) {
  offset = std::min(offset, text.size());
  return 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(offset), '\n'));
}

// nlohmann's message without its "[json.exception...] parse error at line L, column C: " prefix,
// since the line is reported separately.
std::string JsonProblem(const std::string& what) {
  const size_t column = what.find("column ");
  const size_t colon = what.find(": ", column == std::string::npos ? 0 : column);
  const size_t idEnd = what.find("] ");
  if (column != std::string::npos && colon != std::string::npos) return what.substr(colon + 2);
  return idEnd == std::string::npos ? what : what.substr(idEnd + 2);
}

struct JsonDocument {
  Json root;
  std::unordered_map<std::string, int> lines;  // of keys and array elements, by message path
};

// Message paths: "camera.fov_y_deg", "objects[1].transform.scale".
JsonDocument ParseJson(const fs::path& file, const std::string& text) {
  JsonDocument document;
  const char* furthest = text.data();
  // The parser has read one character past a number to find its end; the line is the last one
  // before that character.
  auto currentLine = [&] { return LineAt(text, size_t(std::max<std::ptrdiff_t>(furthest - text.data() - 1, 0))); };
  struct Container {
    bool isArray;
    size_t nextIndex;
    std::string path;
    std::string keyPath;  // objects: the path of the member being read
  };
  std::vector<Container> stack;
  // The path of the value that starts now, recorded with its line when it is an array element.
  auto valuePath = [&]() -> std::string {
    if (stack.empty()) return "";
    Container& parent = stack.back();
    if (!parent.isArray) return parent.keyPath;
    std::string path = parent.path + "[" + std::to_string(parent.nextIndex++) + "]";
    document.lines.emplace(path, currentLine());
    return path;
  };
  const Json::parser_callback_t callback = [&](int, Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start:
      case Json::parse_event_t::array_start: {
        std::string path = valuePath();
        stack.push_back({event == Json::parse_event_t::array_start, 0, std::move(path), ""});
        break;
      }
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        stack.pop_back();
        break;
      case Json::parse_event_t::key: {
        Container& object = stack.back();
        const std::string& key = parsed.get_ref<const std::string&>();
        object.keyPath = object.path.empty() ? key : object.path + "." + key;
        if (!document.lines.emplace(object.keyPath, currentLine()).second)
          throw InputError(file, currentLine(), "duplicate key " + object.keyPath);
        break;
      }
      case Json::parse_event_t::value:
        valuePath();
        break;
    }
    return true;
  };
  try {
    document.root = Json::parse(TrackingIterator(text.data(), &furthest),
                                TrackingIterator(text.data() + text.size(), &furthest), callback);
  } catch (const Json::parse_error& error) {
    throw InputError(file, LineAt(text, error.byte == 0 ? 0 : error.byte - 1), JsonProblem(error.what()));
  } catch (const Json::exception& error) {
    throw InputError(file, currentLine(), JsonProblem(error.what()));
  }
  return document;
}

std::string FormatNumber(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// An allowed interval of a number, with the text error messages give for it.
struct Range {
  double min = -kInfinity;
  double max = kInfinity;
  bool minOpen = false;
  bool maxOpen = false;

  bool Contains(double v) const { return (minOpen ? v > min : v >= min) && (maxOpen ? v < max : v <= max); }
  std::string Text() const {
    if (max == kInfinity) return (minOpen ? "> " : ">= ") + FormatNumber(min);
    return std::string("in ") + (minOpen ? "(" : "[") + FormatNumber(min) + ", " + FormatNumber(max) +
           (maxOpen ? ")" : "]");
  }
};

constexpr Range kAnyNumber{};
constexpr Range kNonNegative{0.0, kInfinity, false, false};
constexpr Range kPositive{0.0, kInfinity, true, false};
constexpr Range kUnit{0.0, 1.0, false, false};
constexpr Range kBelowRightAngle{0.0, 90.0, false, true};

// Reports errors at the line of a message path.
class ErrorReporter {
 public:
  ErrorReporter(fs::path file, std::unordered_map<std::string, int> lines)
      : file_(std::move(file)), lines_(std::move(lines)) {}
  // A key the file leaves out (a default that conflicts) is reported at its parent's line.
  [[noreturn]] void Fail(const std::string& path, const std::string& problem) const {
    throw InputError(file_, LineOf(path), problem);
  }
  // The line of a message path, or of its nearest parent in the file; 0 when none is.
  int LineOf(std::string path) const {
    for (;;) {
      if (const auto line = lines_.find(path); line != lines_.end()) return line->second;
      const size_t parent = path.find_last_of(".[");
      if (parent == std::string::npos) return 0;
      path.resize(parent);
    }
  }

 private:
  fs::path file_;
  std::unordered_map<std::string, int> lines_;
};

// One JSON object of a scene file. Keys outside `known` are errors (a typo must not silently change
// a render); every read checks the type and range and names the key's path when they are wrong.
class ObjectReader {
 public:
  ObjectReader(const ErrorReporter& errors, const Json& node, std::string path,
               std::initializer_list<std::string_view> known)
      : errors_(errors), node_(node), path_(std::move(path)) {
    if (!node.is_object()) errors_.Fail(path_, path_ + " must be an object, got " + node.type_name());
    for (const auto& [key, value] : node.items())
      if (std::find(known.begin(), known.end(), key) == known.end()) {
        std::string list;
        for (std::string_view k : known) list.append(list.empty() ? "" : ", ").append(k);
        errors_.Fail(Path(key), "unknown key " + Path(key) + " (known: " + list + ")");
      }
  }

  std::string Path(std::string_view key) const {
    return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
  }
  const Json* Find(std::string_view key) const {
    const auto it = node_.find(key);
    return it == node_.end() ? nullptr : &*it;
  }
  bool Has(std::string_view key) const { return Find(key) != nullptr; }
  [[noreturn]] void Fail(std::string_view key, const std::string& problem) const {
    errors_.Fail(Path(key), Path(key) + " " + problem);
  }

  std::optional<float> OptionalNumber(std::string_view key, const Range& range = kAnyNumber) const {
    const Json* value = Find(key);
    if (!value) return std::nullopt;
    const float number = ToFloat(key, *value);
    if (!range.Contains(number)) Fail(key, "must be " + range.Text() + ", got " + value->dump());
    return number;
  }
  float Number(std::string_view key, float fallback, const Range& range = kAnyNumber) const {
    return OptionalNumber(key, range).value_or(fallback);
  }

  std::optional<glm::vec3> OptionalVec3(std::string_view key, const Range& range = kAnyNumber) const {
    const Json* value = Find(key);
    if (!value) return std::nullopt;
    return ToVec3(key, *value, range);
  }
  glm::vec3 Vec3(std::string_view key, glm::vec3 fallback, const Range& range = kAnyNumber) const {
    return OptionalVec3(key, range).value_or(fallback);
  }
  glm::vec3 RequiredVec3(std::string_view key) const {
    if (!Has(key)) errors_.Fail(path_, Path(key) + " is required");
    return *OptionalVec3(key);
  }
  glm::vec3 NonZeroDirection(std::string_view key) const {
    // In double, so tiny directions such as [1e-30, 0, 0] normalize too.
    const glm::dvec3 direction = RequiredVec3(key);
    if (direction == glm::dvec3(0.0)) Fail(key, "must not be zero");
    return glm::vec3(glm::normalize(direction));
  }

  std::optional<bool> OptionalBool(std::string_view key) const {
    const Json* value = Find(key);
    if (!value) return std::nullopt;
    if (!value->is_boolean()) Fail(key, std::string("must be true or false, got ") + value->dump());
    return value->get<bool>();
  }

 private:
  float ToFloat(std::string_view key, const Json& value) const {
    if (!value.is_number()) Fail(key, std::string("must be a number, got ") + value.dump());
    const float number = float(value.get<double>());
    if (!std::isfinite(number)) Fail(key, "is out of the float range: " + value.dump());
    return number;
  }
  glm::vec3 ToVec3(std::string_view key, const Json& value, const Range& range) const {
    if (!value.is_array() || value.size() != 3) Fail(key, "must be an array of 3 numbers, got " + value.dump());
    glm::vec3 v;
    for (int i = 0; i < 3; ++i) {
      if (!value[size_t(i)].is_number()) Fail(key, "must be an array of 3 numbers, got " + value.dump());
      v[i] = ToFloat(key, value[size_t(i)]);
      if (!range.Contains(v[i])) Fail(key, "components must be " + range.Text() + ", got " + value.dump());
    }
    return v;
  }

  const ErrorReporter& errors_;
  const Json& node_;
  std::string path_;
};

struct MaterialOverride {
  std::string path;  // for messages
  std::optional<glm::vec3> baseColor;
  std::optional<float> metallic;
  std::optional<float> roughness;
  std::optional<bool> twoSided;
  std::optional<float> alphaCutoff;

  void ApplyTo(Material& m) const {
    m.baseColor = baseColor.value_or(m.baseColor);
    m.metallic = metallic.value_or(m.metallic);
    m.roughness = roughness.value_or(m.roughness);
    m.twoSided = twoSided.value_or(m.twoSided);
    m.alphaCutoff = alphaCutoff.value_or(m.alphaCutoff);
  }
};

struct ObjectDesc {
  fs::path obj;  // one of obj and gltf
  fs::path gltf;
  std::optional<int> camera;  // glTF: which of its cameras the scene uses when it has none of its own
  std::string path;  // "objects[1]", for messages; empty for a bare OBJ
  glm::mat4 transform{1.0f};
  std::optional<MaterialOverride> allMaterials;   // "*"
  std::map<std::string, MaterialOverride> named;  // by MTL material name
};

CameraDesc ReadCamera(const ErrorReporter& errors, const Json& node, const std::string& path = "camera") {
  const ObjectReader r(errors, node, path, {"position", "target", "up", "fov_y_deg", "near"});
  CameraDesc camera;
  camera.position = r.RequiredVec3("position");
  camera.target = r.RequiredVec3("target");
  camera.up = r.Vec3("up", glm::vec3(0.0f, 1.0f, 0.0f));
  camera.fovYDegrees = r.Number("fov_y_deg", 45.0f, Range{0.0, 180.0, true, true});
  camera.nearPlane = r.Number("near", 0.05f, kPositive);
  if (const std::optional<CameraProblem> problem = FindCameraProblem(camera)) r.Fail(problem->key, problem->problem);
  return camera;
}

// "constant" (radiance), "sky" (zenith, horizon, ground, sun_glow, sun_direction: towards the sun,
// by default against the first directional light's direction) or "image" (file relative to the
// scene file, rotation_deg, intensity).
Environment ReadEnvironment(const ErrorReporter& errors, const Json& node, const Scene& scene, const fs::path& folder) {
  if (!node.is_object())
    errors.Fail("environment", std::string("environment must be an object, got ") + node.type_name());
  const Json* type = node.contains("type") ? &node["type"] : nullptr;
  if (type == nullptr) errors.Fail("environment", "environment.type is required (\"constant\", \"sky\" or \"image\")");
  const std::string kind = type->is_string() ? type->get<std::string>() : "";
  if (kind == "constant") {
    const ObjectReader r(errors, node, "environment", {"type", "radiance"});
    Environment environment;
    environment.radiance = r.Vec3("radiance", glm::vec3(0.0f), kNonNegative);
    return environment;
  }
  if (kind == "sky") {
    const ObjectReader r(errors, node, "environment",
                         {"type", "zenith", "horizon", "ground", "sun_glow", "sun_direction"});
    SkyParams sky;
    sky.zenith = r.Vec3("zenith", sky.zenith, kNonNegative);
    sky.horizon = r.Vec3("horizon", sky.horizon, kNonNegative);
    sky.ground = r.Vec3("ground", sky.ground, kNonNegative);
    sky.sunGlow = r.Vec3("sun_glow", sky.sunGlow, kNonNegative);
    if (r.Has("sun_direction")) {
      sky.sunDirection = r.NonZeroDirection("sun_direction");
    } else if (!scene.directionalLights.empty()) {
      sky.sunDirection = -glm::normalize(scene.directionalLights.front().direction);
    }
    return MakeSkyEnvironment(sky);
  }
  if (kind == "image") {
    const ObjectReader r(errors, node, "environment", {"type", "file", "rotation_deg", "intensity"});
    const Json* file = r.Find("file");
    if (file == nullptr || !file->is_string() || file->get<std::string>().empty())
      r.Fail("file",
             "must name the environment image (a string), got " + (file ? file->dump() : std::string("nothing")));
    const fs::path path = folder / file->get<std::string>();
    std::error_code error;
    if (!fs::is_regular_file(path, error)) r.Fail("file", "names a missing file: " + path.string());
    const float rotation = r.Number("rotation_deg", 0.0f);
    const float intensity = r.Number("intensity", 1.0f, kNonNegative);
    return LoadImageEnvironment(path, rotation, intensity);
  }
  errors.Fail("environment.type", "environment.type must be \"constant\", \"sky\" or \"image\", got " + type->dump());
}

void ReadLights(const ErrorReporter& errors, const Json& node, Scene& scene) {
  if (!node.is_array()) errors.Fail("lights", std::string("lights must be an array, got ") + node.type_name());
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string path = "lights[" + std::to_string(i) + "]";
    const Json& light = node[i];
    const auto type = light.is_object() ? light.find("type") : light.end();
    if (!light.is_object() || type == light.end()) errors.Fail(path, path + " must be an object with a \"type\"");
    if (*type == "directional") {
      const ObjectReader r(errors, light, path,
                           {"type", "direction", "irradiance", "angular_diameter_deg", "cast_shadows"});
      DirectionalLight d;
      d.direction = r.NonZeroDirection("direction");
      d.irradiance = r.Vec3("irradiance", glm::vec3(3.0f), kNonNegative);
      d.angularDiameterDegrees = r.Number("angular_diameter_deg", 0.53f, kBelowRightAngle);
      d.castShadows = r.OptionalBool("cast_shadows").value_or(true);
      scene.directionalLights.push_back(d);
    } else if (*type == "spot") {
      const ObjectReader r(
          errors, light, path,
          {"type", "position", "direction", "inner_cone_deg", "outer_cone_deg", "radius", "intensity", "cast_shadows"});
      SpotLight s;
      s.position = r.RequiredVec3("position");
      s.direction = r.NonZeroDirection("direction");
      s.innerConeDegrees = r.Number("inner_cone_deg", 20.0f, kBelowRightAngle);
      s.outerConeDegrees = r.Number("outer_cone_deg", 30.0f, kBelowRightAngle);
      if (s.innerConeDegrees > s.outerConeDegrees)
        r.Fail("inner_cone_deg", "must be <= outer_cone_deg (" + FormatNumber(s.innerConeDegrees) + " > " +
                                     FormatNumber(s.outerConeDegrees) + ")");
      s.radius = r.Number("radius", 0.05f, kNonNegative);
      s.intensity = r.Vec3("intensity", glm::vec3(10.0f), kNonNegative);
      s.castShadows = r.OptionalBool("cast_shadows").value_or(true);
      scene.spotLights.push_back(s);
    } else if (*type == "point") {
      const ObjectReader r(errors, light, path, {"type", "position", "radius", "intensity"});
      PointLight p;
      p.position = r.RequiredVec3("position");
      p.radius = r.Number("radius", 0.05f, kNonNegative);
      p.intensity = r.Vec3("intensity", glm::vec3(10.0f), kNonNegative);
      scene.pointLights.push_back(p);
    } else {
      errors.Fail(path + ".type", path + ".type must be \"directional\", \"spot\" or \"point\", got " + type->dump());
    }
  }
}

// The render block flattened to its values, nested objects ("effects") as dotted keys; the frame
// configuration checks the keys and values (passes/frame/config.h).
void ReadRenderBlock(const ErrorReporter& errors, const Json& node, const std::string& path,
                     std::vector<RenderBlockEntry>& entries) {
  if (!node.is_object()) errors.Fail(path, path + " must be an object, got " + node.type_name());
  for (const auto& [key, value] : node.items()) {
    const std::string keyPath = path + "." + key;
    if (value.is_object()) {
      ReadRenderBlock(errors, value, keyPath, entries);
    } else {
      entries.push_back({keyPath.substr(std::string_view("render.").size()), value.dump(), errors.LineOf(keyPath)});
    }
  }
}

// The image size a camera-less scene file is framed for: its render block's, where it gives a
// valid one (a bad one is reported by the frame configuration), else the default.
int FramingSide(const std::vector<RenderBlockEntry>& render, std::string_view key) {
  for (const RenderBlockEntry& entry : render) {
    if (entry.key != key) continue;
    const Json value = Json::parse(entry.json);
    if (value.is_number_integer() && value.get<int64_t>() >= 1 && value.get<int64_t>() <= kMaxImageSize)
      return int(value.get<int64_t>());
  }
  return kDefaultImageSide;
}

MaterialOverride ReadOverride(const ErrorReporter& errors, const Json& node, const std::string& path) {
  const ObjectReader r(errors, node, path, {"base_color", "metallic", "roughness", "two_sided", "alpha_cutoff"});
  MaterialOverride o;
  o.path = path;
  o.baseColor = r.OptionalVec3("base_color", kUnit);
  o.metallic = r.OptionalNumber("metallic", kUnit);
  o.roughness = r.OptionalNumber("roughness", kUnit);
  o.twoSided = r.OptionalBool("two_sided");
  o.alphaCutoff = r.OptionalNumber("alpha_cutoff", kUnit);
  return o;
}

glm::mat4 ReadTransform(const ErrorReporter& errors, const Json& node, const std::string& path) {
  const ObjectReader r(errors, node, path, {"translate", "rotate_deg", "scale"});
  const glm::vec3 translate = r.Vec3("translate", glm::vec3(0.0f));
  const glm::vec3 rotate = r.Vec3("rotate_deg", glm::vec3(0.0f));
  glm::vec3 scale(1.0f);
  if (const Json* value = r.Find("scale"); value && value->is_number()) {
    scale = glm::vec3(*r.OptionalNumber("scale"));
  } else if (value) {
    if (!value->is_array()) r.Fail("scale", "must be a number or an array of 3 numbers, got " + value->dump());
    scale = *r.OptionalVec3("scale");
  }
  if (scale.x == 0.0f || scale.y == 0.0f || scale.z == 0.0f) r.Fail("scale", "must not be zero");
  // world = T * Rz * Ry * Rx * S * object (docs/user-guide.md "Scene files")
  glm::mat4 m = glm::translate(glm::mat4(1.0f), translate);
  m = glm::rotate(m, glm::radians(rotate.z), glm::vec3(0.0f, 0.0f, 1.0f));
  m = glm::rotate(m, glm::radians(rotate.y), glm::vec3(0.0f, 1.0f, 0.0f));
  m = glm::rotate(m, glm::radians(rotate.x), glm::vec3(1.0f, 0.0f, 0.0f));
  return glm::scale(m, scale);
}

std::vector<ObjectDesc> ReadObjects(const ErrorReporter& errors, const Json& node, const fs::path& folder) {
  if (!node.is_array() || node.empty()) errors.Fail("objects", "objects must be a non-empty array");
  std::vector<ObjectDesc> objects;
  for (size_t i = 0; i < node.size(); ++i) {
    ObjectDesc object;
    object.path = "objects[" + std::to_string(i) + "]";
    const ObjectReader r(errors, node[i], object.path, {"obj", "gltf", "camera", "transform", "materials"});
    const char* kind = r.Has("gltf") ? "gltf" : "obj";
    if (r.Has("obj") == r.Has("gltf"))
      errors.Fail(object.path, object.path + " needs exactly one of \"obj\" and \"gltf\"");
    const Json* file = r.Find(kind);
    if (!file->is_string()) r.Fail(kind, "must be a file name, got " + file->dump());
    (r.Has("gltf") ? object.gltf : object.obj) = folder / file->get<std::string>();
    const fs::path& named = r.Has("gltf") ? object.gltf : object.obj;
    std::error_code error;
    if (!fs::is_regular_file(named, error)) r.Fail(kind, "names a missing file: " + named.string());
    if (const Json* camera = r.Find("camera")) {
      if (!r.Has("gltf") || !camera->is_number_integer() || camera->get<int64_t>() < 0)
        r.Fail("camera", "must be the index of one of the glTF file's cameras, got " + camera->dump());
      object.camera = int(camera->get<int64_t>());
    }
    if (const Json* transform = r.Find("transform"))
      object.transform = ReadTransform(errors, *transform, r.Path("transform"));
    if (const Json* materials = r.Find("materials")) {
      const std::string path = r.Path("materials");
      if (!materials->is_object()) r.Fail("materials", std::string("must be an object, got ") + materials->type_name());
      for (const auto& [name, value] : materials->items()) {
        MaterialOverride o = ReadOverride(errors, value, path + "." + name);
        if (name == "*") {
          object.allMaterials = std::move(o);
        } else {
          object.named.emplace(name, std::move(o));
        }
      }
    }
    objects.push_back(std::move(object));
  }
  return objects;
}

std::string PathKey(const fs::path& file) { return fs::absolute(file).lexically_normal().string(); }

// Appends `source` (object space) to the scene's mesh in world space through `transform`, its
// materials offset by `firstMaterial`.
void AppendMesh(const ErrorReporter& errors, const ObjectDesc& object, const fs::path& file, const Mesh& source,
                uint32_t firstMaterial, Scene& scene) {
  Mesh& mesh = scene.mesh;
  const size_t firstVertex = mesh.positions.size();
  if (firstVertex + source.positions.size() > std::numeric_limits<uint32_t>::max())
    errors.Fail(object.path, object.path + ": the scene has more than 2^32 - 1 vertices");
  const glm::mat3 linear(object.transform);
  const glm::mat3 normalMatrix = glm::transpose(glm::inverse(linear));
  // A mirroring transform turns counter-clockwise triangles clockwise: swap two corners back, and
  // turn the tangent frames' handedness.
  const bool mirrored = glm::determinant(linear) < 0.0f;
  for (size_t v = 0; v < source.positions.size(); ++v) {
    const glm::vec3 p = glm::vec3(object.transform * glm::vec4(source.positions[v], 1.0f));
    const glm::vec3 n =
        source.normals[v] == glm::vec3(0.0f) ? glm::vec3(0.0f) : glm::normalize(normalMatrix * source.normals[v]);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(n.x) ||
        !std::isfinite(n.y) || !std::isfinite(n.z))
      errors.Fail(object.path, (object.path.empty() ? file.string() : object.path) +
                                   ": the transform makes vertex positions or normals non-finite");
    mesh.positions.push_back(p);
    mesh.normals.push_back(n);
  }
  mesh.uvs.insert(mesh.uvs.end(), source.uvs.begin(), source.uvs.end());
  if (!source.tangents.empty()) {
    mesh.tangents.resize(firstVertex, glm::vec4(0.0f));
    for (const glm::vec4& t : source.tangents) {
      const glm::vec3 direction = linear * glm::vec3(t);
      const float length = glm::length(direction);
      mesh.tangents.push_back(glm::vec4(length > 0.0f ? direction / length : direction, mirrored ? -t.w : t.w));
    }
  }
  if (!source.colors.empty()) {
    mesh.colors.resize(firstVertex, glm::vec3(1.0f));
    mesh.colors.insert(mesh.colors.end(), source.colors.begin(), source.colors.end());
  }
  // The optional arrays are per position once any object has them.
  if (!mesh.tangents.empty()) mesh.tangents.resize(mesh.positions.size(), glm::vec4(0.0f));
  if (!mesh.colors.empty()) mesh.colors.resize(mesh.positions.size(), glm::vec3(1.0f));
  for (size_t t = 0; t < source.materials.size(); ++t) {
    const uint32_t* corner = &source.indices[3 * t];
    mesh.indices.push_back(uint32_t(firstVertex) + corner[0]);
    mesh.indices.push_back(uint32_t(firstVertex) + corner[mirrored ? 2 : 1]);
    mesh.indices.push_back(uint32_t(firstVertex) + corner[mirrored ? 1 : 2]);
    mesh.materials.push_back(firstMaterial + source.materials[t]);
  }
}

// Fails when an override names a material the model does not have.
void CheckOverrideNames(const ErrorReporter& errors, const ObjectDesc& object, const fs::path& file,
                        const std::function<bool(const std::string&)>& has) {
  for (const auto& [name, o] : object.named)
    if (!has(name)) errors.Fail(o.path, o.path + ": " + file.filename().string() + " has no material '" + name + "'");
}

Material Overridden(const ObjectDesc& object, Material material) {
  if (object.allMaterials) object.allMaterials->ApplyTo(material);
  if (const auto named = object.named.find(material.name); named != object.named.end()) named->second.ApplyTo(material);
  return material;
}

// A glTF model's lights and cameras, through an object's transform.
void AddGltfLightsAndCameras(const GltfModel& m, const ObjectDesc& object, Scene& scene,
                             std::vector<GltfCamera>& cameras) {
  const glm::mat3 linear(object.transform);
  const auto point = [&](const glm::vec3& p) { return glm::vec3(object.transform * glm::vec4(p, 1.0f)); };
  const auto direction = [&](const glm::vec3& d) { return glm::normalize(linear * d); };
  for (DirectionalLight d : m.directionalLights) {
    d.direction = direction(d.direction);
    scene.directionalLights.push_back(d);
  }
  for (SpotLight s : m.spotLights) {
    s.position = point(s.position);
    s.direction = direction(s.direction);
    scene.spotLights.push_back(s);
  }
  for (PointLight p : m.pointLights) {
    p.position = point(p.position);
    scene.pointLights.push_back(p);
  }
  for (GltfCamera c : m.cameras) {
    c.desc.position = point(c.desc.position);
    c.desc.target = point(c.desc.target);
    c.desc.up = direction(c.desc.up);
    cameras.push_back(c);
  }
}

// Loads each distinct OBJ or glTF file once and each OBJ's (image, encoding) once, and appends every
// object to the scene in world space with its own copy of its materials. `cameras` receives, per
// object, the glTF cameras in world space (empty for an OBJ).
void Bake(const ErrorReporter& errors, const std::vector<ObjectDesc>& objects, Scene& scene,
          std::vector<std::vector<GltfCamera>>& cameras) {
  std::map<std::string, ObjModel> models;
  std::map<std::string, std::pair<GltfModel, int32_t>> gltfModels;  // with its first texture in the scene
  std::map<std::pair<std::string, TextureEncoding>, int32_t> textureIndex;
  auto texture = [&](const fs::path& file, TextureEncoding encoding) -> int32_t {
    if (file.empty()) return kNoTexture;
    const auto [it, inserted] = textureIndex.emplace(std::make_pair(PathKey(file), encoding), 0);
    if (inserted) {
      it->second = int32_t(scene.textures.size());
      scene.textures.push_back(LoadTexture(file, encoding));
    }
    return it->second;
  };

  for (const ObjectDesc& object : objects) {
    cameras.emplace_back();
    const uint32_t firstMaterial = uint32_t(scene.materials.size());
    if (!object.gltf.empty()) {
      const std::string key = PathKey(object.gltf);
      auto model = gltfModels.find(key);
      if (model == gltfModels.end()) {
        GltfModel loaded = LoadGltfModel(object.gltf);
        const int32_t firstTexture = int32_t(scene.textures.size());
        for (Texture& t : loaded.textures) scene.textures.push_back(std::move(t));
        for (const std::string& w : loaded.warnings)
          if (std::find(scene.warnings.begin(), scene.warnings.end(), w) == scene.warnings.end())
            scene.warnings.push_back(w);
        model = gltfModels.emplace(key, std::make_pair(std::move(loaded), firstTexture)).first;
      }
      const auto& [m, firstTexture] = model->second;
      CheckOverrideNames(errors, object, object.gltf, [&](const std::string& name) {
        return std::any_of(m.materials.begin(), m.materials.end(), [&](const Material& g) { return g.name == name; });
      });
      for (const Material& g : m.materials) {
        Material material = Overridden(object, g);
        for (int32_t* t : {&material.baseColorTexture, &material.metallicTexture, &material.roughnessTexture,
                           &material.alphaTexture, &material.normalTexture})
          if (*t != kNoTexture) *t += firstTexture;
        scene.materials.push_back(std::move(material));
      }
      AppendMesh(errors, object, object.gltf, m.mesh, firstMaterial, scene);
      AddGltfLightsAndCameras(m, object, scene, cameras.back());
      if (object.camera && size_t(*object.camera) >= cameras.back().size())
        errors.Fail(object.path + ".camera", object.path + ".camera is " + std::to_string(*object.camera) + " but " +
                                                 object.gltf.filename().string() + " places " +
                                                 std::to_string(cameras.back().size()) + " cameras");
      continue;
    }
    const std::string key = PathKey(object.obj);
    auto model = models.find(key);
    if (model == models.end()) model = models.emplace(key, LoadObjModel(object.obj)).first;
    const ObjModel& m = model->second;
    scene.reorientedTriangles += m.reorientedTriangles;
    CheckOverrideNames(errors, object, object.obj, [&](const std::string& name) {
      return std::any_of(m.materials.begin(), m.materials.end(),
                         [&](const ObjMaterial& om) { return om.material.name == name; });
    });
    for (const ObjMaterial& om : m.materials) {
      Material material = Overridden(object, om.material);
      material.baseColorTexture = texture(om.baseColorTexture, TextureEncoding::kSrgb);
      material.metallicTexture = texture(om.metallicTexture, TextureEncoding::kLinear);
      material.roughnessTexture = texture(om.roughnessTexture, TextureEncoding::kLinear);
      material.alphaTexture = texture(om.alphaTexture, TextureEncoding::kLinear);
      scene.materials.push_back(std::move(material));
    }
    AppendMesh(errors, object, object.obj, m.mesh, firstMaterial, scene);
  }
  if (!scene.pointLights.empty()) {
    const std::string w = scene.source.string() + ": point lights are not shadowed (a shadow needs a cube map)";
    if (std::none_of(scene.warnings.begin(), scene.warnings.end(),
                     [](const std::string& x) { return x.find("point lights are not shadowed") != std::string::npos; }))
      scene.warnings.push_back(w);
  }
}

// The camera a scene without one of its own takes from its glTF objects: the object's "camera", else
// the first camera of the first object that places one.
std::optional<GltfCamera> SceneGltfCamera(const std::vector<ObjectDesc>& objects,
                                          const std::vector<std::vector<GltfCamera>>& cameras) {
  for (size_t i = 0; i < objects.size(); ++i)
    if (objects[i].camera) return cameras[i][size_t(*objects[i].camera)];
  for (const std::vector<GltfCamera>& c : cameras)
    if (!c.empty()) return c.front();
  return std::nullopt;
}

// The whole of a text file; `what` names it in the errors ("scene file").
std::string ReadTextFile(const fs::path& file, const std::string& what) {
  std::error_code error;
  if (!fs::is_regular_file(file, error)) throw InputError(file, what + " not found");
  std::ifstream in(file, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in) throw InputError(file, "cannot read " + what);
  return text;
}

SceneFile LoadJsonScene(const fs::path& file) {
  JsonDocument document = ParseJson(file, ReadTextFile(file, "scene file"));
  if (!document.root.is_object()) throw InputError(file, 1, "the scene must be a JSON object");
  const ErrorReporter errors(file, std::move(document.lines));
  const ObjectReader root(errors, document.root, "", {"camera", "lights", "environment", "objects", "render"});

  SceneFile loaded;
  Scene& scene = loaded.scene;
  scene.source = file;
  if (const Json* render = root.Find("render")) ReadRenderBlock(errors, *render, "render", loaded.render);
  std::optional<CameraDesc> camera;
  if (const Json* node = root.Find("camera")) camera = ReadCamera(errors, *node);
  if (const Json* lights = root.Find("lights")) {
    ReadLights(errors, *lights, scene);
  } else {
    scene.directionalLights.push_back(DefaultLight());
  }
  const fs::path folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
  if (const Json* environment = root.Find("environment"))
    scene.environment = ReadEnvironment(errors, *environment, scene, folder);
  const Json* objects = root.Find("objects");
  if (!objects) errors.Fail("", "objects is required");
  const std::vector<ObjectDesc> descs = ReadObjects(errors, *objects, folder);
  std::vector<std::vector<GltfCamera>> cameras;
  Bake(errors, descs, scene, cameras);
  if (!camera) {
    if (const std::optional<GltfCamera> gltf = SceneGltfCamera(descs, cameras)) camera = gltf->desc;
  }
  scene.camera = camera ? *camera
                        : FrameMesh(scene.mesh, FramingSide(loaded.render, "width"), FramingSide(loaded.render, "height"));
  return loaded;
}

// A bare OBJ or glTF file. An OBJ gets the default light and a camera framing it. A glTF file
// keeps its lights (the default light without any) and takes its first camera (framed as an OBJ
// without one), whose aspect ratio sets the image's height for the default width.
SceneFile LoadModelScene(const fs::path& file, bool gltf) {
  SceneFile loaded;
  Scene& scene = loaded.scene;
  scene.source = file;
  ObjectDesc object;
  (gltf ? object.gltf : object.obj) = file;
  std::vector<std::vector<GltfCamera>> cameras;
  Bake(ErrorReporter(file, {}), {object}, scene, cameras);
  if (!scene.HasLights()) scene.directionalLights.push_back(DefaultLight());
  if (cameras.front().empty()) {
    scene.camera = FrameMesh(scene.mesh, kDefaultImageSide, kDefaultImageSide);
    return loaded;
  }
  scene.camera = cameras.front().front().desc;
  const float aspect = cameras.front().front().aspectRatio;
  if (aspect > 0.0f) {
    const int height = std::clamp(int(std::lround(double(kDefaultImageSide) / double(aspect))), 1, kMaxImageSize);
    loaded.render.push_back({"width", std::to_string(kDefaultImageSide), 0});
    loaded.render.push_back({"height", std::to_string(height), 0});
  }
  return loaded;
}

// A view's "size": "WIDTHxHEIGHT", as --size takes it.
void ReadViewSize(const ObjectReader& r, std::string_view key, int& width, int& height) {
  const Json* size = r.Find(key);
  if (!size) return;
  if (!size->is_string()) r.Fail(key, "must be a string WIDTHxHEIGHT such as \"640x480\", got " + size->dump());
  try {
    ParseImageSize(size->get<std::string>(), width, height);
  } catch (const InputError& e) {
    r.Fail(key, e.what());
  }
}

// One element of "views"; whatever is wrong inside it is the view's error, not the file's.
ViewSpec ReadView(const ErrorReporter& errors, const Json& node, const std::string& path) {
  ViewSpec view;
  try {
    const ObjectReader r(errors, node, path, {"camera", "size", "light_direction"});
    const Json* camera = r.Find("camera");
    if (!camera) errors.Fail(path, r.Path("camera") + " is required");
    view.camera = ReadCamera(errors, *camera, r.Path("camera"));
    ReadViewSize(r, "size", view.width, view.height);
    if (r.Has("light_direction")) view.lightDirection = r.NonZeroDirection("light_direction");
  } catch (const InputError& e) {
    view.error = e.what();
  }
  return view;
}

// "path": {"keyframes": [{"camera": {...}, "light_direction": [...]}, ...], "frames": N, "size": "WxH"}.
// Frame i of N sits at u = i (K - 1) / (N - 1) along the K keyframes (the first frame on the first
// keyframe, the last on the last); each camera value is interpolated linearly between the two
// keyframes around u, in double, and the light direction is the normalised linear blend.
std::vector<ViewSpec> ReadPath(const fs::path& file, const ErrorReporter& errors, const Json& node) {
  const ObjectReader p(errors, node, "path", {"keyframes", "frames", "size"});
  const Json* keyframes = p.Find("keyframes");
  if (!keyframes) errors.Fail("path", "path.keyframes is required");
  if (!keyframes->is_array() || keyframes->empty())
    p.Fail("keyframes", "must be a non-empty array of {\"camera\": {...}}, got " + keyframes->dump());
  const Json* frames = p.Find("frames");
  if (!frames) errors.Fail("path", "path.frames is required");
  constexpr int64_t kMaxFrames = 1000000;
  if (!frames->is_number_integer() || frames->get<int64_t>() < 1 || frames->get<int64_t>() > kMaxFrames)
    p.Fail("frames", "must be a whole number in [1, " + std::to_string(kMaxFrames) + "], got " + frames->dump());
  int width = 0, height = 0;
  ReadViewSize(p, "size", width, height);
  struct Key {
    CameraDesc camera;
    std::optional<glm::vec3> light;
  };
  std::vector<Key> keys;
  for (size_t k = 0; k < keyframes->size(); ++k) {
    const std::string path = "path.keyframes[" + std::to_string(k) + "]";
    const ObjectReader r(errors, (*keyframes)[k], path, {"camera", "light_direction"});
    const Json* camera = r.Find("camera");
    if (!camera) errors.Fail(path, r.Path("camera") + " is required");
    Key key{ReadCamera(errors, *camera, r.Path("camera")), std::nullopt};
    if (r.Has("light_direction")) key.light = r.NonZeroDirection("light_direction");
    if (k > 0 && key.light.has_value() != keys[0].light.has_value())
      errors.Fail(path,
                  "light_direction must be given on every keyframe or on none (" + path +
                      (key.light ? " has it, path.keyframes[0] does not)" : " lacks it, path.keyframes[0] has it)"));
    keys.push_back(key);
  }
  const int count = int(frames->get<int64_t>());
  const int line = errors.LineOf("path");
  std::vector<ViewSpec> views(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    const double u = count == 1 ? 0.0 : double(i) * double(keys.size() - 1) / double(count - 1);
    const size_t segment = std::min(size_t(u), keys.size() >= 2 ? keys.size() - 2 : 0);
    const double t = keys.size() == 1 ? 0.0 : u - double(segment);
    const Key& a = keys[segment];
    const Key& b = keys[std::min(segment + 1, keys.size() - 1)];
    const auto mix = [t](const glm::vec3& x, const glm::vec3& y) {
      return glm::vec3(glm::dvec3(x) + (glm::dvec3(y) - glm::dvec3(x)) * t);
    };
    const auto mixNumber = [t](float x, float y) { return float(double(x) + (double(y) - double(x)) * t); };
    ViewSpec& view = views[size_t(i)];
    view.width = width;
    view.height = height;
    view.camera.position = mix(a.camera.position, b.camera.position);
    view.camera.target = mix(a.camera.target, b.camera.target);
    view.camera.up = mix(a.camera.up, b.camera.up);
    view.camera.fovYDegrees = mixNumber(a.camera.fovYDegrees, b.camera.fovYDegrees);
    view.camera.nearPlane = mixNumber(a.camera.nearPlane, b.camera.nearPlane);
    const std::string frame = "path frame " + std::to_string(i);
    if (const std::optional<CameraProblem> problem = FindCameraProblem(view.camera))
      view.error = InputError(file, line, frame + ": camera." + problem->key + " " + problem->problem).what();
    if (a.light) {
      const glm::dvec3 light = glm::dvec3(mix(*a.light, *b.light));
      if (light == glm::dvec3(0.0))
        view.error = InputError(file, line, frame + ": the light directions of its keyframes cancel out").what();
      else
        view.lightDirection = glm::vec3(glm::normalize(light));
    }
  }
  return views;
}

}  // namespace

std::optional<CameraProblem> FindCameraProblem(const CameraDesc& camera) {
  const glm::dvec3 forward = glm::dvec3(camera.target) - glm::dvec3(camera.position);
  const glm::dvec3 up = camera.up;
  if (forward == glm::dvec3(0.0)) return CameraProblem{"target", "must differ from camera.position"};
  // sin(angle between up and forward) below 1e-6: lookAt would have no sideways axis.
  if (!(glm::length(glm::cross(forward, up)) > 1e-6 * glm::length(forward) * glm::length(up)))
    return CameraProblem{"up", "must not be zero or parallel to target - position"};
  return std::nullopt;
}

std::vector<ViewSpec> LoadViewsFile(const fs::path& file) {
  JsonDocument document = ParseJson(file, ReadTextFile(file, "views file"));
  if (!document.root.is_object())
    throw InputError(file, 1, "a views file must be a JSON object with \"views\" or \"path\"");
  const ErrorReporter errors(file, std::move(document.lines));
  const ObjectReader root(errors, document.root, "", {"views", "path"});
  const Json* views = root.Find("views");
  const Json* path = root.Find("path");
  if (views && path) errors.Fail("path", "give either views or path, not both");
  if (path) return ReadPath(file, errors, *path);
  if (!views) throw InputError(file, 1, "a views file needs \"views\" (a list of views) or \"path\" (keyframes)");
  if (!views->is_array() || views->empty())
    root.Fail("views", "must be a non-empty array of {\"camera\": {...}}, got " + views->dump().substr(0, 60));
  std::vector<ViewSpec> specs;
  specs.reserve(views->size());
  for (size_t i = 0; i < views->size(); ++i)
    specs.push_back(ReadView(errors, (*views)[i], "views[" + std::to_string(i) + "]"));
  return specs;
}

Scene LoadScene(const fs::path& file) { return LoadSceneFile(file).scene; }

SceneFile LoadSceneFile(const fs::path& file) {
  const std::string ext = LowerExtension(file);
  if (ext == ".json") return LoadJsonScene(file);
  if (ext == ".obj") return LoadModelScene(file, false);
  if (ext == ".gltf" || ext == ".glb") return LoadModelScene(file, true);
  throw InputError(file, "unsupported scene format '" + ext + "' (use .json, .obj, .gltf or .glb)");
}

void ParseImageSize(const std::string& text, int& width, int& height) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X'))
    throw InputError("expected WIDTHxHEIGHT such as 1024x768, got '" + text + "'");
  if (w < 1 || h < 1 || w > kMaxImageSize || h > kMaxImageSize)
    throw InputError("width and height must be in [1, " + std::to_string(kMaxImageSize) + "], got " + text);
  width = w;
  height = h;
}

CameraDesc FrameMesh(const Mesh& mesh, int width, int height) {
  SSGI_CHECK_GT(width, 0);
  SSGI_CHECK_GT(height, 0);
  constexpr double kFovYDegrees = 40.0;
  constexpr double kMargin = 1.15;
  glm::dvec3 lo(kInfinity), hi(-kInfinity);
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, glm::dvec3(p));
    hi = glm::max(hi, glm::dvec3(p));
  }
  const glm::dvec3 centre = mesh.positions.empty() ? glm::dvec3(0.0) : (lo + hi) * 0.5;
  double radius = 0.0;
  for (const glm::vec3& p : mesh.positions) radius = std::max(radius, glm::length(glm::dvec3(p) - centre));
  if (!(radius > 0.0)) radius = 1.0;  // empty or single-point mesh

  // The sphere fits the narrower field of view, so portrait images frame it too.
  const double tanHalfY = std::tan(glm::radians(kFovYDegrees) * 0.5);
  const double halfAngle = std::atan(std::min(tanHalfY, tanHalfY * double(width) / double(height)));
  const double distance = radius / std::sin(halfAngle) * kMargin;
  const glm::dvec3 direction = glm::normalize(glm::dvec3(0.6, 0.45, 1.0));

  CameraDesc camera;
  camera.target = glm::vec3(centre);
  camera.position = glm::vec3(centre + direction * distance);
  camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  camera.fovYDegrees = float(kFovYDegrees);
  camera.nearPlane = float(std::max(distance - radius, radius) * 0.02);
  return camera;
}

DirectionalLight DefaultLight() {
  DirectionalLight light;
  light.direction = glm::normalize(glm::vec3(-0.5f, -1.0f, -0.35f));
  light.irradiance = glm::vec3(3.0f);
  light.angularDiameterDegrees = 2.0f;
  light.castShadows = true;
  return light;
}

}  // namespace ssgi
