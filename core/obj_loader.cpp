#include "core/obj_loader.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_map>

#include "core/check.h"
#include "core/error.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;

std::string ReadText(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) throw InputError(file, "cannot read file");
  return text.str();
}

// Calls fn(lineNumber, line) for each line of `text`, without its line break.
template <class Fn>
void ForEachLine(std::string_view text, Fn&& fn) {
  int number = 0;
  size_t begin = 0;
  while (begin < text.size()) {
    const size_t end = std::min(text.find('\n', begin), text.size());
    std::string_view line = text.substr(begin, end - begin);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    fn(++number, line);
    begin = end + 1;
  }
}

// Splits the next space- or tab-separated token off `rest`; empty when none is left.
std::string_view NextToken(std::string_view& rest) {
  const size_t begin = rest.find_first_not_of(" \t");
  if (begin == std::string_view::npos) {
    rest = {};
    return {};
  }
  rest.remove_prefix(begin);
  const size_t end = std::min(rest.find_first_of(" \t"), rest.size());
  const std::string_view token = rest.substr(0, end);
  rest.remove_prefix(end);
  return token;
}

std::string_view TrimTrailing(std::string_view s) {
  const size_t end = s.find_last_not_of(" \t");
  return end == std::string_view::npos ? std::string_view() : s.substr(0, end + 1);
}

std::string Lower(std::string_view s) {
  std::string lower(s);
  for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

// `name` relative to `folder` (or absolute) as an existing file. A component that does not exist
// matches an entry of its folder differing only in letter case (the first in sorted order), for
// assets made on case-insensitive file systems (docs/user-guide.md "Scene files").
std::optional<fs::path> FindFile(const fs::path& folder, const fs::path& name) {
  std::error_code error;
  if (fs::is_regular_file(folder / name, error)) return folder / name;
  fs::path current = name.is_absolute() ? name.root_path() : folder;
  for (const fs::path& part : name.is_absolute() ? name.relative_path() : name) {
    fs::path next = current / part;
    if (!fs::exists(next, error)) {
      const std::string wanted = Lower(part.string());
      std::optional<fs::path> match;
      for (const fs::directory_entry& entry : fs::directory_iterator(current, error)) {
        if (Lower(entry.path().filename().string()) == wanted && (!match || entry.path() < *match))
          match = entry.path();
      }
      if (!match) return std::nullopt;
      next = *match;
    }
    current = next;
  }
  if (!fs::is_regular_file(current, error)) return std::nullopt;
  return current;
}

// An mtllib file name and the line naming it.
struct MaterialLibrary {
  std::string name;
  int line = 0;
};

enum class Element { kPosition, kUv, kNormal };  // in the order of a face corner "p/t/n"
constexpr const char* kElementNames[] = {"position", "texture coordinate", "normal"};

// `token` must lie in a NUL-terminated buffer: strtod stops at the space, line break or NUL after it.
bool IsNumber(std::string_view token, double& value) {
  if (token.find_first_of("xX") != std::string_view::npos) return false;  // hex, which tinyobjloader reads as 0
  char* end = nullptr;
  value = std::strtod(token.data(), &end);
  return end == token.data() + token.size();
}

// Checks what tinyobjloader lets through, naming the line:
// non-numeric or non-finite v/vn/vt values (tinyobjloader silently reads "nan" and "inf" as 0 and
// overflows 1e39 to inf), too few of them, faces with fewer than three corners and indices out of
// range (tinyobjloader only warns and drops quads that use them). Returns the material libraries.
std::vector<MaterialLibrary> ScanObj(const fs::path& file, const std::string& text) {
  std::vector<MaterialLibrary> libraries;
  int counts[3] = {0, 0, 0};
  struct ForwardReference {
    int line;
    Element element;
    long index;
  };
  std::vector<ForwardReference> forwardReferences;  // checked once every element is counted

  auto checkIndex = [&](int line, Element element, std::string_view digits, std::string_view corner) {
    long index = 0;
    const auto [end, status] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
    if (status != std::errc() || end != digits.data() + digits.size())
      throw InputError(file, line, "invalid face corner '" + std::string(corner) + "'");
    const int count = counts[int(element)];
    const std::string what = kElementNames[int(element)];
    if (index == 0) throw InputError(file, line, "face " + what + " index 0 is invalid (OBJ indices start at 1)");
    if (index < 0 && count + index < 0)
      throw InputError(file, line,
                       "face " + what + " index " + std::to_string(index) + " is out of range: only " +
                           std::to_string(count) + " defined before it");
    if (index > count) forwardReferences.push_back({line, element, index});
  };

  ForEachLine(text, [&](int line, std::string_view rest) {
    const std::string_view keyword = NextToken(rest);
    if (keyword == "v" || keyword == "vn" || keyword == "vt") {
      const Element element = keyword == "v" ? Element::kPosition : keyword == "vt" ? Element::kUv : Element::kNormal;
      int numbers = 0;
      for (std::string_view token = NextToken(rest); !token.empty() && token[0] != '#'; token = NextToken(rest)) {
        double value = 0.0;
        if (!IsNumber(token, value))
          throw InputError(file, line,
                           "'" + std::string(keyword) + "' value '" + std::string(token) + "' is not a number");
        if (!std::isfinite(float(value)))
          throw InputError(
              file, line,
              "non-finite " + std::string(kElementNames[int(element)]) + " value '" + std::string(token) + "'");
        ++numbers;
      }
      const int needed = element == Element::kUv ? 1 : 3;
      if (numbers < needed)
        throw InputError(file, line,
                         "'" + std::string(keyword) + "' needs " + std::to_string(needed) + " numbers, got " +
                             std::to_string(numbers));
      ++counts[int(element)];
    } else if (keyword == "f") {
      int corners = 0;
      for (std::string_view corner = NextToken(rest); !corner.empty() && corner[0] != '#'; corner = NextToken(rest)) {
        // "p", "p/t", "p//n" or "p/t/n"
        std::string_view parts = corner;
        for (int element = 0; element < 3; ++element) {
          const size_t slash = std::min(parts.find('/'), parts.size());
          const std::string_view digits = parts.substr(0, slash);
          if (!digits.empty() || element == 0) checkIndex(line, Element(element), digits, corner);
          if (slash == parts.size()) break;
          parts.remove_prefix(slash + 1);
        }
        ++corners;
      }
      if (corners < 3)
        throw InputError(file, line, "face has " + std::to_string(corners) + " corners, needs 3 or more");
    } else if (keyword == "mtllib") {
      for (std::string_view name = NextToken(rest); !name.empty(); name = NextToken(rest))
        libraries.push_back({std::string(name), line});
    }
  });

  for (const ForwardReference& reference : forwardReferences) {
    const int count = counts[int(reference.element)];
    if (reference.index > count)
      throw InputError(file, reference.line,
                       "face " + std::string(kElementNames[int(reference.element)]) + " index " +
                           std::to_string(reference.index) + " is out of range: the file has " + std::to_string(count));
  }
  return libraries;
}

// What tinyobjloader's material_t cannot say: which values the MTL gave (it fills absent ones with
// 0), and where the material and its textures were written.
struct MtlInfo {
  fs::path mtlFile;
  bool hasKd = false;
  bool hasPm = false;
  bool hasPr = false;
  bool hasNs = false;
  int baseColorLine = 0;  // lines of map_Kd, map_Pm, map_Pr, map_d
  int metallicLine = 0;
  int roughnessLine = 0;
  int alphaLine = 0;
};

// Adds the materials of one MTL file to `infos`, keyed by name as tinyobjloader names them (the
// rest of the `newmtl` line after one separator); the first definition of a name wins, as in
// tinyobjloader's material map.
void ScanMtl(const fs::path& mtlFile, const std::string& text, std::unordered_map<std::string, MtlInfo>& infos) {
  MtlInfo ignored;  // for lines before the first newmtl and redefinitions
  MtlInfo* current = &ignored;
  ForEachLine(text, [&](int line, std::string_view rest) {
    std::string_view trimmed = TrimTrailing(rest);
    const std::string_view keyword = NextToken(rest);
    if (keyword == "newmtl") {
      trimmed.remove_prefix(std::min(trimmed.find("newmtl") + 7, trimmed.size()));
      const auto [it, inserted] = infos.emplace(std::string(trimmed), MtlInfo{mtlFile});
      current = inserted ? &it->second : &ignored;
    } else if (keyword == "Kd") {
      current->hasKd = true;
    } else if (keyword == "Pm") {
      current->hasPm = true;
    } else if (keyword == "Pr") {
      current->hasPr = true;
    } else if (keyword == "Ns") {
      current->hasNs = true;
    } else if (keyword == "map_Kd") {
      current->baseColorLine = line;
    } else if (keyword == "map_Pm") {
      current->metallicLine = line;
    } else if (keyword == "map_Pr") {
      current->roughnessLine = line;
    } else if (keyword == "map_d") {
      current->alphaLine = line;
    }
  });
}

// A texture name as tinyobjloader leaves it, made a path: it consumes every MTL texture option
// except -cc (colour correction), and exporters on Windows write backslashes.
fs::path TextureName(const std::string& texname) {
  std::string_view name = TrimTrailing(texname);
  while (name.starts_with("-cc ") || name.starts_with("-cc\t")) {
    name.remove_prefix(3);
    NextToken(name);  // on | off
    name.remove_prefix(std::min(name.find_first_not_of(" \t"), name.size()));
  }
  std::string path(name);
  std::replace(path.begin(), path.end(), '\\', '/');
  return fs::path(path);
}

fs::path ResolveTexture(const std::string& texname, const MtlInfo& info, int line, const std::string& material) {
  if (texname.empty()) return {};
  const fs::path name = TextureName(texname);
  const fs::path folder = info.mtlFile.has_parent_path() ? info.mtlFile.parent_path() : fs::path(".");
  const std::optional<fs::path> found = FindFile(folder, name);
  if (!found)
    throw InputError(info.mtlFile, line, "texture '" + name.string() + "' of material '" + material + "' not found");
  return *found;
}

ObjMaterial ConvertMaterial(const tinyobj::material_t& source, const MtlInfo& info) {
  ObjMaterial out;
  Material& m = out.material;
  m.name = source.name;
  out.baseColorTexture = ResolveTexture(source.diffuse_texname, info, info.baseColorLine, source.name);
  out.metallicTexture = ResolveTexture(source.metallic_texname, info, info.metallicLine, source.name);
  out.roughnessTexture = ResolveTexture(source.roughness_texname, info, info.roughnessLine, source.name);
  out.alphaTexture = ResolveTexture(source.alpha_texname, info, info.alphaLine, source.name);

  if (info.hasKd) {
    m.baseColor = {source.diffuse[0], source.diffuse[1], source.diffuse[2]};
  } else if (!out.baseColorTexture.empty()) {
    m.baseColor = glm::vec3(1.0f);
  }
  if (info.hasPm) {
    m.metallic = std::clamp(source.metallic, 0.0f, 1.0f);
  } else if (!out.metallicTexture.empty()) {
    m.metallic = 1.0f;
  }
  if (info.hasPr) {
    m.roughness = std::clamp(source.roughness, 0.0f, 1.0f);
  } else if (!out.roughnessTexture.empty()) {
    m.roughness = 1.0f;
  } else if (info.hasNs) {
    const float alpha = std::sqrt(2.0f / (std::max(source.shininess, 0.0f) + 2.0f));
    m.roughness = std::sqrt(alpha);
  }
  return out;
}

// Normals for corners the OBJ gives none (or a zero one) for: the area-weighted normals of the
// faces around the corner's position that lie within the crease angle of the corner's own face.
class NormalGenerator {
 public:
  NormalGenerator(const std::vector<float>& positions, const std::vector<tinyobj::index_t>& corners) {
    const size_t triangleCount = corners.size() / 3;
    const size_t positionCount = positions.size() / 3;
    areaNormal_.resize(triangleCount);
    unitNormal_.resize(triangleCount);
    // Doubles: float cross products of metre-scale scans underflow or overflow at the extremes.
    auto position = [&](int i) {
      return glm::dvec3(positions[3 * size_t(i)], positions[3 * size_t(i) + 1], positions[3 * size_t(i) + 2]);
    };
    firstFace_.assign(positionCount + 1, 0);
    for (size_t t = 0; t < triangleCount; ++t) {
      const glm::dvec3 a = position(corners[3 * t].vertex_index);
      const glm::dvec3 b = position(corners[3 * t + 1].vertex_index);
      const glm::dvec3 c = position(corners[3 * t + 2].vertex_index);
      areaNormal_[t] = glm::cross(b - a, c - a);
      const double length = glm::length(areaNormal_[t]);
      unitNormal_[t] = length > 0.0 ? areaNormal_[t] / length : glm::dvec3(0.0);
      for (int k = 0; k < 3; ++k) ++firstFace_[size_t(corners[3 * t + k].vertex_index) + 1];
    }
    for (size_t p = 0; p < positionCount; ++p) firstFace_[p + 1] += firstFace_[p];
    faces_.resize(firstFace_.back());
    std::vector<uint32_t> fill(firstFace_.begin(), firstFace_.end() - 1);
    for (size_t t = 0; t < triangleCount; ++t)
      for (int k = 0; k < 3; ++k) faces_[fill[size_t(corners[3 * t + k].vertex_index)]++] = uint32_t(t);

    // Where every face around a position lies within half the crease angle of their mean, every
    // pair lies within the crease angle, so all corners there share one normal: found once here,
    // this keeps high-valence fans linear instead of quadratic in their valence.
    const double cosHalfCrease = std::cos(glm::radians(double(kCreaseAngleDegrees)) * 0.5);
    smooth_.assign(positionCount, glm::vec3(0.0f));
    for (size_t p = 0; p < positionCount; ++p) {
      glm::dvec3 sum(0.0);
      for (uint32_t i = firstFace_[p]; i < firstFace_[p + 1]; ++i)
        if (Valid(faces_[i])) sum += areaNormal_[faces_[i]];
      const double length = glm::length(sum);
      if (!(length > 0.0)) continue;
      const glm::dvec3 mean = sum / length;
      bool withinHalf = true;
      for (uint32_t i = firstFace_[p]; i < firstFace_[p + 1] && withinHalf; ++i)
        withinHalf = !Valid(faces_[i]) || glm::dot(unitNormal_[faces_[i]], mean) >= cosHalfCrease;
      if (withinHalf) smooth_[p] = glm::vec3(mean);
    }
  }

  glm::vec3 At(size_t triangle, int position) const {
    if (smooth_[size_t(position)] != glm::vec3(0.0f)) return smooth_[size_t(position)];
    const double cosCrease = std::cos(glm::radians(double(kCreaseAngleDegrees)));
    const glm::dvec3 own = unitNormal_[triangle];
    const bool ownValid = Valid(triangle);
    glm::dvec3 sum(0.0);
    for (uint32_t i = firstFace_[size_t(position)]; i < firstFace_[size_t(position) + 1]; ++i) {
      const uint32_t face = faces_[i];
      // A zero-area face has no direction of its own: it takes the smooth normal of the position.
      if (Valid(face) && (!ownValid || glm::dot(own, unitNormal_[face]) >= cosCrease)) sum += areaNormal_[face];
    }
    const double length = glm::length(sum);
    if (length > 0.0 && std::isfinite(length)) return glm::vec3(sum / length);
    return ownValid ? glm::vec3(own) : glm::vec3(0.0f, 1.0f, 0.0f);
  }

 private:
  bool Valid(size_t face) const { return unitNormal_[face] != glm::dvec3(0.0); }

  std::vector<glm::dvec3> areaNormal_;  // per triangle; length = twice the area
  std::vector<glm::dvec3> unitNormal_;  // per triangle; zero for zero-area triangles
  std::vector<uint32_t> firstFace_;     // per position: its range in faces_
  std::vector<uint32_t> faces_;         // the triangles at each position, in file order
  std::vector<glm::vec3> smooth_;       // per position: the shared normal, or zero
};

size_t HashWords(std::initializer_list<uint64_t> words) {
  size_t h = 0;
  for (uint64_t v : words) h = (h ^ v) * 0x100000001b3ull;
  return h;
}

struct PositionBitsHash {
  size_t operator()(const std::array<uint32_t, 3>& bits) const { return HashWords({bits[0], bits[1], bits[2]}); }
};

// Makes the winding consistent where real scenes' meshes flip it (Sibenik has 59 such edges,
// Dabrovic Sponza 4): a flipped triangle would be culled as a back face by the rasterizer and the
// reference alike, and would turn its generated normals inside out. Triangles meeting across an
// edge used by exactly two of them (positions compared by value, so duplicated vertices weld) must
// traverse it in opposite directions; each connected set of triangles keeps the winding of the
// larger part of its area, and the rest are turned (corners 1 and 2 swapped, attributes with them).
// Non-manifold edges (three or more triangles) do not link, and a non-orientable set keeps the first
// winding found. Returns the number of triangles turned.
size_t OrientConsistently(const std::vector<float>& positions, std::vector<tinyobj::index_t>& corners) {
  const size_t triangleCount = corners.size() / 3;
  std::unordered_map<std::array<uint32_t, 3>, uint32_t, PositionBitsHash> weldedOf;
  std::vector<uint32_t> welded(positions.size() / 3);
  for (size_t p = 0; p < welded.size(); ++p) {
    std::array<uint32_t, 3> bits;
    for (int k = 0; k < 3; ++k) bits[size_t(k)] = std::bit_cast<uint32_t>(positions[3 * p + size_t(k)] + 0.0f);
    welded[p] = weldedOf.emplace(bits, uint32_t(weldedOf.size())).first->second;
  }
  struct EdgeUse {
    uint64_t key;        // the welded end points, lower first
    uint32_t triangle;
    bool forward;        // traversed from the lower end point to the higher
  };
  std::vector<EdgeUse> uses;
  uses.reserve(corners.size());
  for (size_t t = 0; t < triangleCount; ++t) {
    for (size_t k = 0; k < 3; ++k) {
      const uint32_t a = welded[size_t(corners[3 * t + k].vertex_index)];
      const uint32_t b = welded[size_t(corners[3 * t + (k + 1) % 3].vertex_index)];
      if (a != b) uses.push_back({(uint64_t(std::min(a, b)) << 32) | std::max(a, b), uint32_t(t), a < b});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return x.key != y.key ? x.key < y.key : x.triangle < y.triangle;
  });
  // Links across manifold edges: `same` when both traverse it the same way (one must turn).
  struct Link {
    uint32_t other;
    bool same;
  };
  std::vector<std::vector<Link>> links(triangleCount);
  for (size_t i = 0; i < uses.size();) {
    size_t j = i + 1;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    if (j - i == 2 && uses[i].triangle != uses[i + 1].triangle) {
      const bool same = uses[i].forward == uses[i + 1].forward;
      links[uses[i].triangle].push_back({uses[i + 1].triangle, same});
      links[uses[i + 1].triangle].push_back({uses[i].triangle, same});
    }
    i = j;
  }
  auto area = [&](size_t t) {
    const auto position = [&](size_t corner) {
      const size_t p = 3 * size_t(corners[corner].vertex_index);
      return glm::dvec3(positions[p], positions[p + 1], positions[p + 2]);
    };
    return glm::length(glm::cross(position(3 * t + 1) - position(3 * t), position(3 * t + 2) - position(3 * t)));
  };
  constexpr uint8_t kUnvisited = 2;
  std::vector<uint8_t> turned(triangleCount, kUnvisited);  // 1: opposite to the set's first triangle
  size_t turnedCount = 0;
  std::vector<uint32_t> component;
  for (size_t seed = 0; seed < triangleCount; ++seed) {
    if (turned[seed] != kUnvisited || links[seed].empty()) continue;
    component.assign(1, uint32_t(seed));
    turned[seed] = 0;
    double areaAsSeed = 0.0, areaOpposite = 0.0;
    for (size_t next = 0; next < component.size(); ++next) {
      const uint32_t t = component[next];
      (turned[t] ? areaOpposite : areaAsSeed) += area(t);
      for (const Link& link : links[t]) {
        if (turned[link.other] != kUnvisited) continue;
        turned[link.other] = uint8_t(turned[t] ^ uint8_t(link.same));
        component.push_back(link.other);
      }
    }
    const uint8_t flip = areaOpposite > areaAsSeed ? 0 : 1;  // the minority's mark
    for (const uint32_t t : component) {
      if (turned[t] != flip) continue;
      std::swap(corners[3 * size_t(t) + 1], corners[3 * size_t(t) + 2]);
      ++turnedCount;
    }
  }
  return turnedCount;
}

// The first line of tinyobjloader's error text and the OBJ line it names ("... line 12 ...").
std::pair<int, std::string> ParseTinyObjError(const std::string& error) {
  int line = 0;
  for (size_t at = error.find("line "); at != std::string::npos && line == 0; at = error.find("line ", at + 1)) {
    const char* digits = error.c_str() + at + 5;
    std::from_chars(digits, error.c_str() + error.size(), line);
  }
  std::string first = error.substr(0, error.find('\n'));
  return {line, first.empty() ? "cannot parse the OBJ file" : first};
}

// Gives tinyobjloader the MTL texts read by LoadObjModel, all at its first mtllib line. (Its own
// readers only warn when a file is missing, read just the first existing file of an mtllib line,
// and ObjReader::ParseFromString re-reads its exhausted stream at every further mtllib line,
// adding an unnamed material each time.)
class MaterialsReadAbove : public tinyobj::MaterialReader {
 public:
  explicit MaterialsReadAbove(const std::string& text) : text_(text) {}
  bool operator()(const std::string&, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* materialMap, std::string* warning, std::string* error) override {
    if (!read_) {
      std::istringstream in(text_);
      tinyobj::LoadMtl(materialMap, materials, &in, warning, error);
      read_ = true;
    }
    return true;
  }

 private:
  const std::string& text_;
  bool read_ = false;
};

struct CornerKey {
  int position;
  int uv;
  int normal;  // the OBJ normal index, or -1 for a generated normal (then its bits tell corners apart)
  uint32_t nx, ny, nz;
  bool operator==(const CornerKey&) const = default;
};

struct CornerKeyHash {
  size_t operator()(const CornerKey& k) const {
    return HashWords({uint64_t(uint32_t(k.position)), uint64_t(uint32_t(k.uv)), uint64_t(uint32_t(k.normal)),
                      uint64_t(k.nx), uint64_t(k.ny), uint64_t(k.nz)});
  }
};

}  // namespace

ObjModel LoadObjModel(const fs::path& file) {
  std::error_code error;
  if (!fs::is_regular_file(file, error)) throw InputError(file, "OBJ file not found");
  const std::string objText = ReadText(file);
  const std::vector<MaterialLibrary> libraries = ScanObj(file, objText);

  // The MTL files are read here, so a missing one is an error and each material's file is known.
  const fs::path folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::unordered_map<std::string, MtlInfo> mtlInfos;
  std::vector<fs::path> mtlFiles;
  std::string mtlText;
  for (const MaterialLibrary& library : libraries) {
    const std::optional<fs::path> mtlFile = FindFile(folder, fs::path(library.name));
    if (!mtlFile) throw InputError(file, library.line, "material library '" + library.name + "' not found");
    if (std::find(mtlFiles.begin(), mtlFiles.end(), *mtlFile) != mtlFiles.end()) continue;
    mtlFiles.push_back(*mtlFile);
    const std::string text = ReadText(*mtlFile);
    ScanMtl(*mtlFile, text, mtlInfos);
    mtlText.append(text).append("\n");
  }

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warning, problem;
  std::istringstream objStream(objText);
  MaterialsReadAbove materialReader(mtlText);
  if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warning, &problem, &objStream, &materialReader,
                        /*triangulate=*/true, /*default_vcols_fallback=*/false) ||
      !problem.empty()) {
    const auto [line, message] = ParseTinyObjError(problem);
    throw InputError(file, line, message);
  }

  ObjModel model;
  for (const tinyobj::material_t& material : materials) {
    const auto info = mtlInfos.find(material.name);
    model.materials.push_back(ConvertMaterial(
        material, info != mtlInfos.end() ? info->second : MtlInfo{mtlFiles.empty() ? file : mtlFiles.front()}));
  }

  std::vector<tinyobj::index_t> corners;
  std::vector<int> triangleMaterials;
  for (const tinyobj::shape_t& shape : shapes) {
    for (const auto n : shape.mesh.num_face_vertices) SSGI_CHECK_EQ(int(n), 3);
    corners.insert(corners.end(), shape.mesh.indices.begin(), shape.mesh.indices.end());
    triangleMaterials.insert(triangleMaterials.end(), shape.mesh.material_ids.begin(), shape.mesh.material_ids.end());
  }
  if (corners.empty()) throw InputError(file, "the OBJ file has no faces");
  SSGI_CHECK_EQ(corners.size(), triangleMaterials.size() * 3);

  model.reorientedTriangles = OrientConsistently(attrib.vertices, corners);
  const NormalGenerator generator(attrib.vertices, corners);
  Mesh& mesh = model.mesh;
  std::unordered_map<CornerKey, uint32_t, CornerKeyHash> vertexOf;
  for (size_t c = 0; c < corners.size(); ++c) {
    const tinyobj::index_t& corner = corners[c];
    glm::dvec3 normal(0.0);
    if (corner.normal_index >= 0) {
      const size_t n = 3 * size_t(corner.normal_index);
      normal = glm::dvec3(attrib.normals[n], attrib.normals[n + 1], attrib.normals[n + 2]);
    }
    const double length = glm::length(normal);
    CornerKey key{corner.vertex_index, corner.texcoord_index, corner.normal_index, 0, 0, 0};
    glm::vec3 unitNormal;
    if (length > 0.0) {
      unitNormal = glm::vec3(normal / length);
    } else {
      unitNormal = generator.At(c / 3, corner.vertex_index);
      key.normal = -1;
      key.nx = std::bit_cast<uint32_t>(unitNormal.x);
      key.ny = std::bit_cast<uint32_t>(unitNormal.y);
      key.nz = std::bit_cast<uint32_t>(unitNormal.z);
    }
    const auto [it, inserted] = vertexOf.emplace(key, uint32_t(mesh.positions.size()));
    if (inserted) {
      const size_t p = 3 * size_t(corner.vertex_index);
      mesh.positions.emplace_back(attrib.vertices[p], attrib.vertices[p + 1], attrib.vertices[p + 2]);
      mesh.normals.push_back(unitNormal);
      if (corner.texcoord_index >= 0) {
        const size_t t = 2 * size_t(corner.texcoord_index);
        mesh.uvs.emplace_back(attrib.texcoords[t], attrib.texcoords[t + 1]);
      } else {
        mesh.uvs.emplace_back(0.0f, 0.0f);
      }
    }
    mesh.indices.push_back(it->second);
  }

  bool needsDefault = false;
  for (int id : triangleMaterials) needsDefault |= id < 0 || size_t(id) >= model.materials.size();
  const uint32_t defaultMaterial = uint32_t(model.materials.size());
  if (needsDefault) {
    ObjMaterial fallback;
    fallback.material.name = kDefaultMaterialName;
    model.materials.push_back(fallback);
  }
  for (int id : triangleMaterials)
    mesh.materials.push_back(id < 0 || size_t(id) >= defaultMaterial ? defaultMaterial : uint32_t(id));
  return model;
}

}  // namespace ssgi
