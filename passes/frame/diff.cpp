// Pass-by-pass comparison of two frame dumps.
#include "passes/frame/diff.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>

#include "core/check.h"
#include "core/error.h"
#include "core/image_compare.h"
#include "core/parallel.h"
#include "core/raster/raster.h"
#include "passes/frame/dump.h"
#include "passes/shadow_map.h"

namespace ssgi {
namespace {

using Json = nlohmann::json;

std::string LayerId(const std::string& part, const std::string& name) {
  return part == DumpPartName(DumpPart::kImage, 0) || part.empty() ? name : part + ":" + name;
}

// The float's position on the ordered line of floats (-0 and +0 both 0), so that adjacent floats
// are 1 apart.
int64_t OrderedFloat(uint32_t bits) {
  return (bits & 0x80000000u) != 0 ? -int64_t(bits & 0x7FFFFFFFu) : int64_t(bits);
}

float AsFloat(uint32_t bits) {
  float value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}

bool Matches(const std::string& pattern, const std::string& id) {
  if (!pattern.empty() && pattern.back() == '*') return id.compare(0, pattern.size() - 1, pattern, 0, pattern.size() - 1) == 0;
  return pattern == id;
}

// Distance from point p to the segment a-b.
double SegmentDistance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
  const glm::dvec2 ab = b - a;
  const double length2 = glm::dot(ab, ab);
  const double t = length2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / length2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

// The part of triangle `t` in front of the near plane and behind the far plane (clip w - z >= 0,
// z >= 0, as the oracle clips it), in pixels on the view's y-down screen; returns its vertex count
// (0 to 5).
int ScreenPolygon(const Mesh& mesh, const ViewProjection& view, uint32_t t, glm::dvec2* out) {
  glm::dvec4 polygon[2][5];
  for (int k = 0; k < 3; ++k) {
    const glm::vec3 p = mesh.positions[mesh.indices[size_t(t) * 3 + size_t(k)]];
    polygon[0][k] = glm::dvec4(view.viewProjection * glm::vec4(p, 1.0f));
  }
  int count = 3, current = 0;
  for (int plane = 0; plane < 2 && count > 0; ++plane) {
    const auto distance = [plane](const glm::dvec4& v) { return plane == 0 ? v.w - v.z : v.z; };
    int written = 0;
    for (int i = 0; i < count; ++i) {
      const glm::dvec4& a = polygon[current][i];
      const glm::dvec4& b = polygon[current][(i + 1) % count];
      const double da = distance(a), db = distance(b);
      if (da >= 0.0) polygon[current ^ 1][written++] = a;
      if ((da >= 0.0) != (db >= 0.0)) polygon[current ^ 1][written++] = a + (b - a) * (da / (da - db));
    }
    count = written;
    current ^= 1;
  }
  for (int k = 0; k < count; ++k) {
    const glm::dvec4& v = polygon[current][k];
    out[k] = {(v.x / v.w * 0.5 + 0.5) * view.width, (0.5 - v.y / v.w * 0.5) * view.height};
  }
  return count;
}

// How far a pixel's centre lies from the nearest edge of a triangle that may cover it, in pixels,
// and how far is within rounding.
class EdgeDistances {
 public:
  explicit EdgeDistances(double rounding) : rounding_(rounding) {}
  virtual ~EdgeDistances() = default;
  double Rounding() const { return rounding_; }
  virtual double Distance(int x, int y) const = 0;

 private:
  double rounding_;
};

// How far each pixel's centre lies from the nearest edge of a triangle the oracle draws there or
// next to it, or the port draws there (the drawn part of it: clipped at the near plane), in pixels:
// computed on first asking, per pixel. Bands of several layers may ask about one pixel at once; each
// computes the same answer, so the memo is relaxed atomics.
class EdgePixels : public EdgeDistances {
 public:
  EdgePixels(const CoverageGeometry& geometry, const ExrLayer& oracleTriangles, const ExrLayer* portTriangles)
      : EdgeDistances(geometry.rounding),
        geometry_(geometry),
        oracle_(oracleTriangles),
        port_(portTriangles),
        known_(oracleTriangles.samples.size()) {
    SSGI_CHECK_EQ(oracle_.samples.size(), size_t(oracle_.width) * size_t(oracle_.height));
    for (std::atomic<uint32_t>& distance : known_) distance.store(kUnknown, std::memory_order_relaxed);
  }

  double Distance(int x, int y) const override {
    std::atomic<uint32_t>& known = known_[size_t(y) * size_t(oracle_.width) + size_t(x)];
    uint32_t bits = known.load(std::memory_order_relaxed);
    if (bits == kUnknown) {
      bits = std::bit_cast<uint32_t>(float(Measure(x, y)));
      known.store(bits, std::memory_order_relaxed);
    }
    return double(std::bit_cast<float>(bits));
  }

 private:
  static constexpr uint32_t kUnknown = 0xFFFFFFFFu;  // a NaN no distance is

  double Measure(int x, int y) const {
    // The triangles of the 3x3 neighbourhood and the port's, each once.
    uint32_t triangles[10];
    size_t count = 0;
    const auto add = [&](uint32_t t) {
      if (std::find(triangles, triangles + count, t) == triangles + count) triangles[count++] = t;
    };
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= oracle_.width || ny >= oracle_.height) continue;
        add(oracle_.samples[size_t(ny) * size_t(oracle_.width) + size_t(nx)]);
      }
    if (port_ != nullptr) add(port_->samples[size_t(y) * size_t(oracle_.width) + size_t(x)]);
    const glm::dvec2 centre(x + 0.5, y + 0.5);
    double nearest = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < count; ++i) {
      const uint32_t t = triangles[i];
      if (t == kNoTriangle || size_t(t) >= geometry_.mesh.TriangleCount()) continue;
      glm::dvec2 corners[5];
      const int n = ScreenPolygon(geometry_.mesh, geometry_.view, t, corners);
      for (int k = 0; k < n; ++k)
        nearest = std::min(nearest, SegmentDistance(centre, corners[k], corners[(k + 1) % n]));
    }
    return nearest;
  }

  const CoverageGeometry& geometry_;
  const ExrLayer& oracle_;
  const ExrLayer* port_;
  mutable std::vector<std::atomic<uint32_t>> known_;
};

// How far each texel's centre lies from the nearest edge of any triangle of the mesh seen from
// `view` (its part between the near and far planes): for a target with no triangle index, such as
// the shadow map, where every triangle is drawn with both faces. The triangles are binned into
// cells of kCell texels on the first question, which comes only where two maps differ.
class MeshEdges : public EdgeDistances {
 public:
  MeshEdges(const Mesh& mesh, const ViewProjection& view, double rounding)
      : EdgeDistances(rounding),
        mesh_(mesh),
        view_(view),
        cellsX_((view.width + kCell - 1) / kCell),
        cellsY_((view.height + kCell - 1) / kCell) {}

  double Distance(int x, int y) const override {
    std::call_once(binned_, [this] { Bin(); });
    const glm::dvec2 centre(x + 0.5, y + 0.5);
    double nearest = std::numeric_limits<double>::infinity();
    for (const uint32_t p : cells_[size_t(y / kCell) * size_t(cellsX_) + size_t(x / kCell)]) {
      const Polygon& polygon = polygons_[p];
      for (int k = 0; k < polygon.count; ++k)
        nearest =
            std::min(nearest, SegmentDistance(centre, polygon.corners[k], polygon.corners[(k + 1) % polygon.count]));
    }
    return nearest;
  }

 private:
  static constexpr int kCell = 32;
  struct Polygon {
    glm::dvec2 corners[5];
    int count;
  };

  // Each drawn polygon into the cells its bounds, widened by the rounding, overlap.
  void Bin() const {
    cells_.resize(size_t(cellsX_) * size_t(cellsY_));
    for (uint32_t t = 0; t < mesh_.TriangleCount(); ++t) {
      Polygon polygon;
      polygon.count = ScreenPolygon(mesh_, view_, t, polygon.corners);
      if (polygon.count < 3) continue;
      glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
      for (int k = 0; k < polygon.count; ++k) {
        lo = glm::min(lo, polygon.corners[k]);
        hi = glm::max(hi, polygon.corners[k]);
      }
      const auto cell = [&](double v, int cells) {
        return int(std::clamp(std::floor(v / kCell), 0.0, double(cells - 1)));
      };
      if (!(hi.x >= -Rounding() && hi.y >= -Rounding() && lo.x <= view_.width + Rounding() &&
            lo.y <= view_.height + Rounding()))
        continue;
      const uint32_t index = uint32_t(polygons_.size());
      polygons_.push_back(polygon);
      for (int cy = cell(lo.y - Rounding(), cellsY_); cy <= cell(hi.y + Rounding(), cellsY_); ++cy)
        for (int cx = cell(lo.x - Rounding(), cellsX_); cx <= cell(hi.x + Rounding(), cellsX_); ++cx)
          cells_[size_t(cy) * size_t(cellsX_) + size_t(cx)].push_back(index);
    }
  }

  const Mesh& mesh_;
  const ViewProjection& view_;
  int cellsX_, cellsY_;
  mutable std::once_flag binned_;
  mutable std::vector<Polygon> polygons_;
  mutable std::vector<std::vector<uint32_t>> cells_;
};

// Whether sample a (port) is within tolerance of b (oracle), and the differences measured.
struct SampleDifference {
  double absolute = 0.0;
  uint64_t ulp = 0;
  bool ulpMeasured = false;  // a float pair, not both within the absolute tolerance of zero
  bool within = true;
  double used = 0.0;  // within: the share of the most lenient bound the difference uses, 0 to 1
};

SampleDifference CompareSample(uint32_t a, uint32_t b, bool isUint, const LayerTolerance& tolerance) {
  SampleDifference d;
  if (a == b) return d;
  if (isUint) {
    d.absolute = std::fabs(double(a) - double(b));
    d.within = !tolerance.exact && tolerance.absolute > 0.0 && d.absolute <= tolerance.absolute;
    if (d.within) d.used = d.absolute / tolerance.absolute;
    return d;
  }
  const float fa = AsFloat(a), fb = AsFloat(b);
  if (std::isnan(fa) || std::isnan(fb)) {
    d.absolute = std::numeric_limits<double>::infinity();
    d.ulp = UINT64_MAX;
    d.ulpMeasured = true;
    d.within = std::isnan(fa) && std::isnan(fb) && !tolerance.exact;
    return d;
  }
  d.absolute = std::fabs(double(fa) - double(fb));
  if (std::isinf(fa) || std::isinf(fb)) d.absolute = fa == fb ? 0.0 : std::numeric_limits<double>::infinity();
  d.ulp = uint64_t(std::llabs(OrderedFloat(a) - OrderedFloat(b)));
  d.ulpMeasured = !(tolerance.absolute > 0.0 && std::fabs(double(fa)) <= tolerance.absolute &&
                    std::fabs(double(fb)) <= tolerance.absolute);
  if (tolerance.exact) {
    d.within = false;
    return d;
  }
  const double relativeBound = tolerance.relative * std::fabs(double(fb));
  d.within = d.ulp == 0 || (tolerance.absolute > 0.0 && d.absolute <= tolerance.absolute) ||
             (tolerance.relative > 0.0 && d.absolute <= relativeBound) || (tolerance.ulp > 0 && d.ulp <= tolerance.ulp);
  if (!d.within || d.ulp == 0) return d;
  // The share of the most lenient bound the difference uses.
  double used = 1.0;
  if (tolerance.absolute > 0.0) used = std::min(used, d.absolute / tolerance.absolute);
  if (tolerance.relative > 0.0 && relativeBound > 0.0) used = std::min(used, d.absolute / relativeBound);
  if (tolerance.ulp > 0) used = std::min(used, double(d.ulp) / double(tolerance.ulp));
  d.used = used;
  return d;
}

// Rows [yBegin, yEnd) of one layer compared: the sums and extremes DiffDumps combines in band order.
struct BandDiff {
  double sumSquares = 0.0, maxAbsolute = 0.0, worst = -1.0, toleranceUsed = 0.0;
  uint64_t maxUlp = 0;
  bool ulpMeasured = false, hardFailed = false;
  size_t samples = 0, overTolerance = 0, edgePixels = 0;
  double maxEdgeDistance = 0.0;
  int worstX = -1, worstY = -1;
};

BandDiff CompareBand(const ExrLayer& oracle, const ExrLayer& port, const LayerTolerance& tolerance,
                     const EdgeDistances* edges, int yBegin, int yEnd) {
  BandDiff band;
  for (int y = yBegin; y < yEnd; ++y) {
    for (int x = 0; x < oracle.width; ++x) {
      const size_t i = size_t(y) * size_t(oracle.width) + size_t(x);
      if (port.samples[i] == oracle.samples[i]) {
        ++band.samples;
        continue;
      }
      const SampleDifference d = CompareSample(port.samples[i], oracle.samples[i], oracle.isUint, tolerance);
      if (d.absolute == 0.0 && d.ulp == 0) {
        ++band.samples;
        continue;
      }
      if (tolerance.coverage && edges != nullptr) {
        const double distance = edges->Distance(x, y);
        if (distance <= edges->Rounding()) {
          ++band.edgePixels;
          band.maxEdgeDistance = std::max(band.maxEdgeDistance, distance);
          continue;
        }
      }
      ++band.samples;
      band.maxAbsolute = std::max(band.maxAbsolute, d.absolute);
      if (d.ulpMeasured) {
        band.maxUlp = std::max(band.maxUlp, d.ulp);
        band.ulpMeasured = true;
      }
      band.sumSquares += std::isfinite(d.absolute) ? d.absolute * d.absolute : 0.0;
      if (d.within) {
        band.toleranceUsed = std::max(band.toleranceUsed, d.used);
        continue;
      }
      ++band.overTolerance;
      if (d.absolute > tolerance.hardFail) band.hardFailed = true;
      if (d.absolute > band.worst) {
        band.worst = d.absolute;
        band.worstX = x;
        band.worstY = y;
      }
    }
  }
  return band;
}

// A layer of both files, before its samples are compared: fails at once when size or type differ.
LayerDiff CheckLayerPair(const std::string& id, FramePass pass, const ExrLayer& oracle, const ExrLayer* port) {
  LayerDiff diff;
  diff.id = id;
  diff.pass = pass;
  if (port == nullptr) {
    diff.presence = LayerPresence::kOracleOnly;
    diff.problem = "not in the port's file";
    return diff;
  }
  if (port->width != oracle.width || port->height != oracle.height) {
    diff.problem = "size differs: " + std::to_string(port->width) + "x" + std::to_string(port->height) + ", the oracle's " +
                   std::to_string(oracle.width) + "x" + std::to_string(oracle.height);
    diff.ok = false;
    return diff;
  }
  if (port->isUint != oracle.isUint) {
    diff.problem = std::string("type differs: ") + (port->isUint ? "uint32" : "float") + ", the oracle's " +
                   (oracle.isUint ? "uint32" : "float");
    diff.typeDiffers = true;
    diff.ok = false;
    return diff;
  }
  const size_t count = size_t(oracle.width) * size_t(oracle.height);
  SSGI_CHECK_EQ(oracle.samples.size(), count);
  SSGI_CHECK_EQ(port->samples.size(), count);
  diff.compared = true;
  return diff;
}

// The bands' results in band order, and the layer's verdict.
void CombineBands(const std::vector<BandDiff>& bands, const LayerTolerance& tolerance, bool isUint, LayerDiff& diff) {
  double sumSquares = 0.0, worst = -1.0;
  bool hardFailed = false, ulpMeasured = false;
  for (const BandDiff& band : bands) {
    sumSquares += band.sumSquares;
    diff.samples += band.samples;
    diff.overTolerance += band.overTolerance;
    diff.edgePixels += band.edgePixels;
    diff.maxEdgeDistance = std::max(diff.maxEdgeDistance, band.maxEdgeDistance);
    diff.maxAbsolute = std::max(diff.maxAbsolute, band.maxAbsolute);
    diff.maxUlp = std::max(diff.maxUlp, band.maxUlp);
    diff.toleranceUsed = std::max(diff.toleranceUsed, band.toleranceUsed);
    ulpMeasured = ulpMeasured || band.ulpMeasured;
    hardFailed = hardFailed || band.hardFailed;
    if (band.worst > worst) {
      worst = band.worst;
      diff.worstX = band.worstX;
      diff.worstY = band.worstY;
    }
  }
  // Equal layers measure 0 ULP; differences all near zero measure none.
  diff.ulpMeasured = !isUint && (ulpMeasured || diff.maxAbsolute == 0.0);
  diff.rmse = diff.samples > 0 ? std::sqrt(sumSquares / double(diff.samples)) : 0.0;
  diff.percentOver = diff.samples > 0 ? 100.0 * double(diff.overTolerance) / double(diff.samples) : 0.0;
  diff.ok = !hardFailed && (diff.overTolerance == 0 || diff.percentOver <= tolerance.percent);
  diff.close = diff.ok && (diff.toleranceUsed > kCloseShare ||
                           (diff.overTolerance > 0 && diff.percentOver > kCloseShare * tolerance.percent));
  if (hardFailed) diff.problem = "a sample is off by more than the hard limit";
}

// The line (from 1) of a byte offset of `text`.
int LineAt(const std::string& text, size_t offset) {
  offset = std::min(offset, text.size());
  return 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(offset), '\n'));
}

// The line on which element `index` of the top-level object's array "layers" starts, or 0: nlohmann
// keeps no positions of parsed values, so the text is scanned for it (strings and nesting only;
// the text has parsed already).
int RuleLine(const std::string& text, size_t index) {
  int depth = 0;
  bool inString = false, escaped = false, inLayers = false, expectElement = false;
  std::string string, key;
  size_t element = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        inString = false;
      } else {
        string += c;
      }
      continue;
    }
    if (std::isspace(static_cast<unsigned char>(c))) continue;
    if (inLayers && depth == 2 && expectElement && c != ']') {
      if (element == index) return LineAt(text, i);
      ++element;
      expectElement = false;
    }
    switch (c) {
      case '"':
        inString = true;
        string.clear();
        break;
      case ':':
        key = string;
        break;
      case ',':
        if (inLayers && depth == 2) expectElement = true;
        break;
      case '[':
      case '{':
        ++depth;
        if (c == '[' && depth == 2 && key == "layers") inLayers = expectElement = true;
        break;
      case ']':
      case '}':
        if (inLayers && depth == 2) inLayers = false;
        --depth;
        break;
      default:
        break;
    }
  }
  return 0;
}

LayerTolerance ParseTolerance(const Json& rule, const std::filesystem::path& file, int line, size_t index) {
  LayerTolerance t;
  const std::string where = "layers[" + std::to_string(index) + "]";
  for (const auto& [key, value] : rule.items()) {
    const auto number = [&] {
      if (!value.is_number() || !(value.get<double>() >= 0.0))
        throw InputError(file, line, where + "." + key + ": must be a number >= 0");
      return value.get<double>();
    };
    if (key == "match") continue;
    if (key == "exact" || key == "coverage") {
      if (!value.is_boolean()) throw InputError(file, line, where + "." + key + ": must be true or false");
      (key == "exact" ? t.exact : t.coverage) = value.get<bool>();
    } else if (key == "absolute") {
      t.absolute = number();
    } else if (key == "relative") {
      t.relative = number();
    } else if (key == "ulp") {
      t.ulp = uint64_t(number());
    } else if (key == "percent") {
      t.percent = number();
    } else if (key == "hardfail") {
      t.hardFail = number();
    } else if (key != "why") {
      throw InputError(file, line,
                       where + ": unknown key '" + key +
                           "' (keys: match, exact, absolute, relative, ulp, percent, hardfail, coverage, why)");
    }
  }
  return t;
}

}  // namespace

LayerTolerance DiffThresholds::For(const std::string& layerId) const {
  for (const auto& [pattern, tolerance] : rules)
    if (Matches(pattern, layerId)) return tolerance;
  LayerTolerance exact;
  exact.exact = true;
  return exact;
}

DiffThresholds LoadDiffThresholds(const std::filesystem::path& file, int extendsDepth) {
  constexpr int kMaxExtends = 8;  // a chain this long is a loop
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file, "cannot open the thresholds file");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Json json;
  try {
    json = Json::parse(text);
  } catch (const Json::parse_error& e) {
    // e.byte counts the bytes read, the offending one included; its message leads with
    // "[json.exception.parse_error.N] parse error at line L, column C: ", which file:line replaces.
    std::string what = e.what();
    const size_t detail = what.find(": ", what.find("parse error"));
    if (detail != std::string::npos) what = what.substr(detail + 2);
    throw InputError(file, LineAt(text, e.byte > 0 ? e.byte - 1 : 0), "not valid JSON: " + what);
  }
  if (!json.is_object() || !json.contains("layers") || !json["layers"].is_array())
    throw InputError(file, "must be an object with an array \"layers\"");
  DiffThresholds thresholds;
  size_t index = 0;
  for (const Json& rule : json["layers"]) {
    const int line = RuleLine(text, index);
    if (!rule.is_object() || !rule.contains("match") || !rule["match"].is_string())
      throw InputError(file, line, "layers[" + std::to_string(index) + "]: must be an object with a string \"match\"");
    thresholds.rules.emplace_back(rule["match"].get<std::string>(), ParseTolerance(rule, file, line, index));
    ++index;
  }
  // A file that loosens or tightens a few layers of another: that file's rules after its own.
  if (json.contains("extends")) {
    if (!json["extends"].is_string()) throw InputError(file, "\"extends\" must be a thresholds file's path");
    const std::filesystem::path base = file.parent_path() / json["extends"].get<std::string>();
    if (extendsDepth >= kMaxExtends)
      throw InputError(file, "extends more than " + std::to_string(kMaxExtends) + " files");
    const DiffThresholds extended = LoadDiffThresholds(base, extendsDepth + 1);
    thresholds.rules.insert(thresholds.rules.end(), extended.rules.begin(), extended.rules.end());
  }
  return thresholds;
}

DiffReport DiffDumps(const ExrFile& oracle, const ExrFile& port, const DiffThresholds& thresholds,
                     const std::optional<CoverageGeometry>& geometry) {
  DiffReport report;
  const std::string image = DumpPartName(DumpPart::kImage, 0);
  std::optional<EdgePixels> edges;
  std::optional<MeshEdges> shadowEdges;
  if (geometry && geometry->shadowView != nullptr)
    shadowEdges.emplace(geometry->mesh, *geometry->shadowView, geometry->rounding);
  if (geometry) {
    if (const ExrLayer* triangles = FindDumpLayer(oracle, image, "raster.triangle")) {
      // The port's triangles only where they can be indexed like the oracle's.
      const ExrLayer* portTriangles = FindDumpLayer(port, image, "raster.triangle");
      if (portTriangles != nullptr && (portTriangles->width != triangles->width ||
                                       portTriangles->height != triangles->height || !portTriangles->isUint))
        portTriangles = nullptr;
      edges.emplace(*geometry, *triangles, portTriangles);
    }
  }
  // The layers in pipeline order, each with its pair of samples where it is compared.
  struct Pair {
    const ExrLayer* oracle = nullptr;
    const ExrLayer* port = nullptr;
    LayerTolerance tolerance;
    const EdgeDistances* edges = nullptr;  // where coverage is judged
  };
  std::vector<Pair> pairs;
  std::set<std::pair<std::string, std::string>> seen;
  const auto compare = [&](const std::string& part, const std::string& name, FramePass pass) {
    const ExrLayer* a = FindDumpLayer(oracle, part, name);
    if (a == nullptr) return false;
    seen.insert({a->part, name});
    const std::string id = LayerId(part, name);
    const ExrLayer* b = FindDumpLayer(port, part, name);
    report.layers.push_back(CheckLayerPair(id, pass, *a, b));
    const EdgeDistances* layerEdges = nullptr;
    if (part == DumpPartName(DumpPart::kShadowMap, 0)) {
      if (shadowEdges) layerEdges = &*shadowEdges;
    } else if (edges) {
      layerEdges = &*edges;
    }
    pairs.push_back({a, b, thresholds.For(id), layerEdges});
    return true;
  };
  const std::vector<DumpLayer>& catalogue = DumpLayers();
  for (size_t i = 0; i < catalogue.size(); ++i) {
    const DumpLayer& layer = catalogue[i];
    if (layer.part == DumpPart::kImage || layer.part == DumpPart::kShadowMap || layer.part == DumpPart::kSkyVolume ||
        layer.part == DumpPart::kBounceHalf) {
      compare(DumpPartName(layer.part, 0), std::string(layer.name), layer.pass);
      continue;
    }
    // A pyramid's channels, level by level.
    size_t end = i;
    while (end < catalogue.size() && catalogue[end].part == layer.part) ++end;
    for (int level = 0;; ++level) {
      bool any = false;
      for (size_t k = i; k < end; ++k)
        any = compare(DumpPartName(layer.part, level), std::string(catalogue[k].name), catalogue[k].pass) || any;
      if (!any) break;
    }
    i = end - 1;
  }

  // Every compared layer's fixed bands of rows, all on all threads.
  constexpr int kBandRows = 64;
  struct Band {
    size_t layer;
    int yBegin, yEnd;
  };
  std::vector<Band> bands;
  std::vector<size_t> firstBand(report.layers.size() + 1, 0);
  for (size_t l = 0; l < report.layers.size(); ++l) {
    firstBand[l] = bands.size();
    if (!report.layers[l].compared) continue;
    for (int y = 0; y < pairs[l].oracle->height; y += kBandRows)
      bands.push_back({l, y, std::min(y + kBandRows, pairs[l].oracle->height)});
  }
  firstBand[report.layers.size()] = bands.size();
  std::vector<BandDiff> results(bands.size());
  ParallelFor("diff layers", bands.size(), [&](size_t i) {
    const Pair& pair = pairs[bands[i].layer];
    results[i] = CompareBand(*pair.oracle, *pair.port, pair.tolerance, pair.edges, bands[i].yBegin, bands[i].yEnd);
  });
  for (size_t l = 0; l < report.layers.size(); ++l) {
    if (!report.layers[l].compared) continue;
    CombineBands(std::vector<BandDiff>(results.begin() + std::ptrdiff_t(firstBand[l]),
                                       results.begin() + std::ptrdiff_t(firstBand[l + 1])),
                 pairs[l].tolerance, pairs[l].oracle->isUint, report.layers[l]);
  }

  for (const ExrLayer& layer : port.layers) {
    const std::string part = layer.part.empty() ? image : layer.part;
    if (seen.count({part, layer.name}) || seen.count({layer.part, layer.name})) continue;
    LayerDiff extra;
    extra.id = LayerId(part, layer.name);
    extra.pass = FramePass::kTonemap;  // unused: not compared
    extra.presence = LayerPresence::kPortOnly;
    extra.problem = "not in the oracle's file";
    report.layers.push_back(extra);
  }
  // The first failing pass in pipeline order (the port's extra layers, not compared, never fail).
  for (const LayerDiff& layer : report.layers) {
    if (layer.ok) continue;
    report.ok = false;
    if (!report.firstFailingPass || layer.pass < *report.firstFailingPass) report.firstFailingPass = layer.pass;
  }
  return report;
}

std::optional<ViewProjection> DiffShadowView(const ExrFile& oracle, const ExrFile& port, const Scene& scene,
                                             const FrameConfig& config) {
  const std::string image = DumpPartName(DumpPart::kImage, 0), shadowMap = DumpPartName(DumpPart::kShadowMap, 0);
  if (FindDumpLayer(oracle, shadowMap, "depthKey") == nullptr || FindDumpLayer(port, shadowMap, "depthKey") == nullptr)
    return std::nullopt;
  const std::vector<size_t> lights = ShadowCastingLights(scene);
  const ExrLayer* word2 = FindDumpLayer(oracle, image, "gbuffer.word2");
  if (word2 == nullptr || word2->samples.empty()) word2 = FindDumpLayer(port, image, "gbuffer.word2");
  if (lights.empty() || word2 == nullptr || word2->samples.empty() || word2->isUint == false) return std::nullopt;
  GBuffer gbuffer = MakeGBuffer(word2->width, word2->height, config.normalEncoding);
  for (size_t y = 0; y < size_t(word2->height); ++y)
    std::copy_n(word2->samples.begin() + std::ptrdiff_t(y * size_t(word2->width)), word2->width,
                gbuffer.word[GBufferWord::kDepth].MutableRow(y));
  const ViewProjection camera = MakePerspective(scene.camera, word2->width, word2->height);
  size_t receivers = 0;
  return FitShadowMapView(scene, camera, gbuffer, lights.front(), config.shadowMap, KernelPath::kSimd, receivers);
}

ExrChannelFilter OracleLayersToRead(const ExrFile& port) {
  return [&port](const std::string& part, const std::string& name) {
    const std::string image = DumpPartName(DumpPart::kImage, 0);
    const std::string dumpPart = part.empty() ? image : part;
    // The visibility buffer's triangles judge the image's coverage; word 2 fits the light's view that
    // judges the shadow map's.
    const bool portHasShadowMap = FindDumpLayer(port, DumpPartName(DumpPart::kShadowMap, 0), "depthKey") != nullptr;
    return FindDumpLayer(port, dumpPart, name) != nullptr || (dumpPart == image && name == "raster.triangle") ||
           (dumpPart == image && name == "gbuffer.word2" && portHasShadowMap);
  };
}

std::vector<uint8_t> LayerDiffHeatmap(const ExrFile& oracle, const ExrFile& port, const std::string& layerId,
                                      int& width, int& height) {
  const size_t colon = layerId.find(':');
  const std::string part = colon == std::string::npos ? DumpPartName(DumpPart::kImage, 0) : layerId.substr(0, colon);
  const std::string name = colon == std::string::npos ? layerId : layerId.substr(colon + 1);
  const ExrLayer* a = FindDumpLayer(port, part, name);
  const ExrLayer* b = FindDumpLayer(oracle, part, name);
  if (a == nullptr || b == nullptr || a->width != b->width || a->height != b->height || a->isUint != b->isUint) return {};
  width = a->width;
  height = a->height;
  std::vector<double> difference(a->samples.size());
  double largest = 0.0;
  for (size_t i = 0; i < difference.size(); ++i) {
    const double va = a->isUint ? double(a->samples[i]) : double(AsFloat(a->samples[i]));
    const double vb = b->isUint ? double(b->samples[i]) : double(AsFloat(b->samples[i]));
    difference[i] = a->samples[i] == b->samples[i] ? 0.0 : std::isfinite(va - vb) ? std::fabs(va - vb) : HUGE_VAL;
    if (std::isfinite(difference[i])) largest = std::max(largest, difference[i]);
  }
  std::vector<uint8_t> rgb(difference.size() * 3);
  for (size_t i = 0; i < difference.size(); ++i) {
    // Scaled to the largest finite difference; a non-finite one is white.
    const double t = difference[i] == 0.0 ? 0.0 : std::isfinite(difference[i]) && largest > 0.0 ? difference[i] / largest : 1.0;
    HeatmapColour(t, &rgb[i * 3]);
  }
  return rgb;
}

std::string DiffReportJson(const DiffReport& report) {
  Json json;
  json["ok"] = report.ok;
  json["firstFailingPass"] = report.firstFailingPass ? Json(std::string(FramePassName(*report.firstFailingPass))) : Json();
  json["layers"] = Json::array();
  for (const LayerDiff& layer : report.layers) {
    Json entry = {{"id", layer.id},
                  {"pass", std::string(FramePassName(layer.pass))},
                  {"compared", layer.compared},
                  {"ok", layer.ok}};
    if (layer.presence != LayerPresence::kBoth)
      entry["onlyIn"] = layer.presence == LayerPresence::kOracleOnly ? "oracle" : "port";
    if (layer.typeDiffers) entry["typeDiffers"] = true;
    if (!layer.problem.empty()) entry["problem"] = layer.problem;
    if (layer.compared) {
      entry["close"] = layer.close;
      entry["maxAbsolute"] = std::isfinite(layer.maxAbsolute) ? Json(layer.maxAbsolute) : Json("inf");
      entry["maxUlp"] = layer.ulpMeasured ? Json(layer.maxUlp) : Json();
      entry["toleranceUsed"] = layer.toleranceUsed;
      entry["percentOver"] = layer.percentOver;
      entry["rmse"] = layer.rmse;
      entry["samples"] = layer.samples;
      entry["overTolerance"] = layer.overTolerance;
      entry["edgePixels"] = layer.edgePixels;
      entry["maxEdgeDistance"] = layer.maxEdgeDistance;
      if (layer.worstX >= 0) entry["worst"] = {layer.worstX, layer.worstY};
    }
    json["layers"].push_back(entry);
  }
  return json.dump(2);
}

}  // namespace ssgi
