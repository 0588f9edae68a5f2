// Pass-by-pass comparison of two frame dumps.
#include "passes/frame/diff.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/image_compare.h"
#include "core/raster/raster.h"
#include "passes/frame/dump.h"

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

// Which pixels lie within kCoverageRounding of an edge of a triangle the oracle draws there or next
// to them, or the port draws there: computed on first asking, per pixel.
class EdgePixels {
 public:
  EdgePixels(const CoverageGeometry& geometry, const ExrLayer& oracleTriangles, const ExrLayer* portTriangles)
      : geometry_(geometry), oracle_(oracleTriangles), port_(portTriangles),
        known_(oracleTriangles.samples.size(), kUnknown) {}

  bool At(int x, int y) {
    const size_t i = size_t(y) * size_t(oracle_.width) + size_t(x);
    if (known_[i] == kUnknown) known_[i] = Classify(x, y) ? kEdge : kInterior;
    return known_[i] == kEdge;
  }

 private:
  static constexpr int8_t kUnknown = -1, kInterior = 0, kEdge = 1;

  bool Classify(int x, int y) const {
    std::set<uint32_t> triangles;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= oracle_.width || ny >= oracle_.height) continue;
        triangles.insert(oracle_.samples[size_t(ny) * size_t(oracle_.width) + size_t(nx)]);
      }
    if (port_ != nullptr) triangles.insert(port_->samples[size_t(y) * size_t(oracle_.width) + size_t(x)]);
    const glm::dvec2 centre(x + 0.5, y + 0.5);
    for (uint32_t t : triangles) {
      if (t == kNoTriangle || size_t(t) >= geometry_.mesh.TriangleCount()) continue;
      glm::dvec2 corners[3];
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 p = geometry_.mesh.positions[geometry_.mesh.indices[size_t(t) * 3 + size_t(k)]];
        const glm::dvec4 clip = glm::dvec4(geometry_.view.viewProjection * glm::vec4(p, 1.0f));
        // A vertex behind the camera: the drawn triangle is clipped, its edges are not these; its
        // pixels are not judged.
        if (!(clip.w > 0.0)) return true;
        corners[k] = {(clip.x / clip.w * 0.5 + 0.5) * geometry_.view.width,
                      (0.5 - clip.y / clip.w * 0.5) * geometry_.view.height};
      }
      for (int k = 0; k < 3; ++k)
        if (SegmentDistance(centre, corners[k], corners[(k + 1) % 3]) <= kCoverageRounding) return true;
    }
    return false;
  }

  const CoverageGeometry& geometry_;
  const ExrLayer& oracle_;
  const ExrLayer* port_;
  std::vector<int8_t> known_;
};

// Whether sample a (port) is within tolerance of b (oracle), and the differences measured.
struct SampleDifference {
  double absolute = 0.0;
  uint64_t ulp = 0;
  bool within = true;
};

SampleDifference CompareSample(uint32_t a, uint32_t b, bool isUint, const LayerTolerance& tolerance) {
  SampleDifference d;
  if (a == b) return d;
  if (isUint) {
    d.absolute = std::fabs(double(a) - double(b));
    d.within = !tolerance.exact && tolerance.absolute > 0.0 && d.absolute <= tolerance.absolute;
    return d;
  }
  const float fa = AsFloat(a), fb = AsFloat(b);
  if (std::isnan(fa) || std::isnan(fb)) {
    d.absolute = std::numeric_limits<double>::infinity();
    d.ulp = UINT64_MAX;
    d.within = std::isnan(fa) && std::isnan(fb) && !tolerance.exact;
    return d;
  }
  d.absolute = std::fabs(double(fa) - double(fb));
  if (std::isinf(fa) || std::isinf(fb)) d.absolute = fa == fb ? 0.0 : std::numeric_limits<double>::infinity();
  d.ulp = uint64_t(std::llabs(OrderedFloat(a) - OrderedFloat(b)));
  if (tolerance.exact) {
    d.within = false;
  } else {
    d.within = d.ulp == 0 || (tolerance.absolute > 0.0 && d.absolute <= tolerance.absolute) ||
               (tolerance.relative > 0.0 && d.absolute <= tolerance.relative * std::fabs(double(fb))) ||
               (tolerance.ulp > 0 && d.ulp <= tolerance.ulp);
  }
  return d;
}

LayerDiff CompareLayer(const std::string& id, FramePass pass, const ExrLayer& oracle, const ExrLayer* port,
                       const LayerTolerance& tolerance, EdgePixels* edges) {
  LayerDiff diff;
  diff.id = id;
  diff.pass = pass;
  if (port == nullptr) {
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
    diff.ok = false;
    return diff;
  }
  diff.compared = true;
  double sumSquares = 0.0, worst = -1.0;
  bool hardFailed = false;
  for (int y = 0; y < oracle.height; ++y) {
    for (int x = 0; x < oracle.width; ++x) {
      const size_t i = size_t(y) * size_t(oracle.width) + size_t(x);
      const SampleDifference d = CompareSample(port->samples[i], oracle.samples[i], oracle.isUint, tolerance);
      if (d.absolute == 0.0 && d.ulp == 0) {
        ++diff.samples;
        continue;
      }
      if (tolerance.coverage && edges != nullptr && edges->At(x, y)) {
        ++diff.edgePixels;
        continue;
      }
      ++diff.samples;
      diff.maxAbsolute = std::max(diff.maxAbsolute, d.absolute);
      diff.maxUlp = std::max(diff.maxUlp, d.ulp);
      sumSquares += std::isfinite(d.absolute) ? d.absolute * d.absolute : 0.0;
      if (d.within) continue;
      ++diff.overTolerance;
      if (d.absolute > tolerance.hardFail) hardFailed = true;
      if (d.absolute > worst) {
        worst = d.absolute;
        diff.worstX = x;
        diff.worstY = y;
      }
    }
  }
  diff.rmse = diff.samples > 0 ? std::sqrt(sumSquares / double(diff.samples)) : 0.0;
  const double percentOver = diff.samples > 0 ? 100.0 * double(diff.overTolerance) / double(diff.samples) : 0.0;
  diff.ok = !hardFailed && (diff.overTolerance == 0 || percentOver <= tolerance.percent);
  if (hardFailed) diff.problem = "a sample is off by more than the hard limit";
  return diff;
}

LayerTolerance ParseTolerance(const Json& rule, const std::filesystem::path& file, size_t index) {
  LayerTolerance t;
  const std::string where = "layers[" + std::to_string(index) + "]";
  for (const auto& [key, value] : rule.items()) {
    const auto number = [&] {
      if (!value.is_number() || !(value.get<double>() >= 0.0))
        throw InputError(file, where + "." + key + ": must be a number >= 0");
      return value.get<double>();
    };
    if (key == "match") continue;
    if (key == "exact" || key == "coverage") {
      if (!value.is_boolean()) throw InputError(file, where + "." + key + ": must be true or false");
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
      throw InputError(file, where + ": unknown key '" + key +
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

DiffThresholds LoadDiffThresholds(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file, "cannot open the thresholds file");
  Json json;
  try {
    json = Json::parse(in);
  } catch (const Json::parse_error& e) {
    throw InputError(file, std::string("not valid JSON: ") + e.what());
  }
  if (!json.is_object() || !json.contains("layers") || !json["layers"].is_array())
    throw InputError(file, "must be an object with an array \"layers\"");
  DiffThresholds thresholds;
  size_t index = 0;
  for (const Json& rule : json["layers"]) {
    if (!rule.is_object() || !rule.contains("match") || !rule["match"].is_string())
      throw InputError(file, "layers[" + std::to_string(index) + "]: must be an object with a string \"match\"");
    thresholds.rules.emplace_back(rule["match"].get<std::string>(), ParseTolerance(rule, file, index));
    ++index;
  }
  return thresholds;
}

DiffReport DiffDumps(const ExrFile& oracle, const ExrFile& port, const DiffThresholds& thresholds,
                     const std::optional<CoverageGeometry>& geometry) {
  DiffReport report;
  const std::string image = DumpPartName(DumpPart::kImage, 0);
  std::optional<EdgePixels> edges;
  if (geometry) {
    if (const ExrLayer* triangles = FindDumpLayer(oracle, image, "raster.triangle"))
      edges.emplace(*geometry, *triangles, FindDumpLayer(port, image, "raster.triangle"));
  }
  std::set<std::pair<std::string, std::string>> seen;
  const auto compare = [&](const std::string& part, const std::string& name, FramePass pass) {
    const ExrLayer* a = FindDumpLayer(oracle, part, name);
    if (a == nullptr) return false;
    seen.insert({a->part, name});
    const std::string id = LayerId(part, name);
    report.layers.push_back(
        CompareLayer(id, pass, *a, FindDumpLayer(port, part, name), thresholds.For(id), edges ? &*edges : nullptr));
    return true;
  };
  const std::vector<DumpLayer>& catalogue = DumpLayers();
  for (size_t i = 0; i < catalogue.size(); ++i) {
    const DumpLayer& layer = catalogue[i];
    if (layer.part == DumpPart::kImage || layer.part == DumpPart::kShadowMap || layer.part == DumpPart::kSkyVolume) {
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
  for (const ExrLayer& layer : port.layers) {
    const std::string part = layer.part.empty() ? image : layer.part;
    if (seen.count({part, layer.name}) || seen.count({layer.part, layer.name})) continue;
    LayerDiff extra;
    extra.id = LayerId(part, layer.name);
    extra.pass = FramePass::kTonemap;  // unused: not compared
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
    if (!layer.problem.empty()) entry["problem"] = layer.problem;
    if (layer.compared) {
      entry["maxAbsolute"] = std::isfinite(layer.maxAbsolute) ? Json(layer.maxAbsolute) : Json("inf");
      entry["maxUlp"] = layer.maxUlp;
      entry["rmse"] = layer.rmse;
      entry["samples"] = layer.samples;
      entry["overTolerance"] = layer.overTolerance;
      entry["edgePixels"] = layer.edgePixels;
      if (layer.worstX >= 0) entry["worst"] = {layer.worstX, layer.worstY};
    }
    json["layers"].push_back(entry);
  }
  return json.dump(2);
}

}  // namespace ssgi
