// Pass-by-pass comparison of two frame dumps (passes/frame/dump.h): the oracle's and a port's.
// Every layer both hold is compared in pipeline order against a named tolerance (docs/pipeline.md
// §Matching rules; the defaults in data/diff_thresholds.json), in the style of OpenImageIO's
// testsuite (failthresh, failpercent, hardfail); rasterization coverage differences are judged the
// way the VK-GL-CTS rasterization verifier judges them: a pixel whose centre lies within rounding
// distance of a triangle edge may differ, any other may not.
#pragma once

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/image_io.h"
#include "core/mesh.h"
#include "passes/frame/config.h"
#include "passes/frame/frame.h"

namespace ssgi {

// How far one layer of a port may stray from the oracle's.
struct LayerTolerance {
  bool exact = false;  // every sample's bits equal
  // A float sample within any one of these of the oracle's is within tolerance (0 = not used; all
  // 0 with exact false: equal values, +0 and -0 alike).
  double absolute = 0.0;
  double relative = 0.0;  // of the oracle's magnitude
  uint64_t ulp = 0;       // units in the last place, counted over the ordered float line
  double percent = 0.0;   // share of samples allowed beyond the tolerance, in percent
  double hardFail = std::numeric_limits<double>::infinity();  // a sample off by more fails the layer
  // A rasterizer output: samples that differ at pixels whose centre lies within kCoverageRounding
  // of an edge of a triangle either side covers there (its part in front of the near plane) are
  // allowed (needs the scene's geometry).
  bool coverage = false;
};

// Tolerances by layer: the first rule whose pattern matches the layer's id ("direct.R",
// "hiz.3:Y"; a pattern may end in '*' to match any suffix) applies; no match is `exact`.
struct DiffThresholds {
  std::vector<std::pair<std::string, LayerTolerance>> rules;
  LayerTolerance For(const std::string& layerId) const;
};
// Reads a thresholds file (JSON, the format of data/diff_thresholds.json). Throws InputError
// naming the file and the key for anything malformed.
// "extends": "OTHER.json" (relative to the file) appends OTHER's rules after the file's own, so a
// file can change a few layers of another; `extendsDepth` counts the files extended so far.
DiffThresholds LoadDiffThresholds(const std::filesystem::path& file, int extendsDepth = 0);

// How far from an edge (the exact one, through the unsnapped vertices) a pixel centre may be and
// still be covered differently by two rasterizers: two steps of an 8-bit sub-pixel grid. A
// rasterizer with GL_SUBPIXEL_BITS >= 8 moves a vertex by at most half a step per axis (0.0028
// pixel), its float32 viewport transform by a few ULP more; measured with llvmpipe, 0.0019 pixel at
// most (docs/pipeline.md, Matching rules). Fewer bits need 2^(1 - bits).
inline constexpr double kCoverageRounding = 1.0 / 128.0;
// The same distance for a rasterizer of `subpixelBits` bits: two of its sub-pixel steps.
inline double CoverageRounding(int subpixelBits) { return std::ldexp(1.0, 1 - subpixelBits); }

// The geometry behind the oracle's visibility buffer, for the coverage classification, and the
// distance from an edge within which a pixel may be covered differently; with `shadowView`, the
// shadow map's texels are judged too, against every triangle seen from the light.
struct CoverageGeometry {
  const Mesh& mesh;
  const ViewProjection& view;
  double rounding = kCoverageRounding;
  const ViewProjection* shadowView = nullptr;
};

// Where a layer is: in both files (compared when of one size and type), or in one only (listed,
// not compared).
enum class LayerPresence { kBoth, kOracleOnly, kPortOnly };

// A passing layer is close to its tolerance when a sample within it uses more than this share of
// it (its difference over what the most lenient of the absolute, relative and ULP bounds allows),
// or when more than this share of the samples `percent` allows are beyond it: a port's change that
// moves it a little further may fail it.
inline constexpr double kCloseShare = 0.5;

struct LayerDiff {
  std::string id;  // the layer's name, "part:name" outside the part "frame"
  FramePass pass;
  LayerPresence presence = LayerPresence::kBoth;
  bool compared = false;     // in both files with the same size and type
  bool typeDiffers = false;  // uint32 in one file, float in the other: not compared, fails
  std::string problem;       // why not compared, or why it failed outright ("size differs: ...")
  double maxAbsolute = 0.0;
  // The largest ULP difference of the samples that differ, but those whose two values both lie
  // within the layer's absolute tolerance of zero, where ULPs measure nothing (1e-30 against 0 is
  // a billion ULP). ulpMeasured is false for integer layers and where every differing sample is
  // such a pair.
  uint64_t maxUlp = 0;
  bool ulpMeasured = true;
  double rmse = 0.0;
  size_t samples = 0;
  size_t overTolerance = 0;  // samples beyond the tolerance, edge pixels excluded
  size_t edgePixels = 0;     // samples that differ at an edge pixel (coverage layers), allowed
  double maxEdgeDistance = 0.0;  // the farthest of those from its edge, in pixels (at most the rounding)
  int worstX = -1, worstY = -1;  // where the largest difference beyond tolerance is
  double toleranceUsed = 0.0;    // the largest share of its tolerance a sample within it uses, 0 to 1
  double percentOver = 0.0;      // overTolerance as a percentage of samples
  bool ok = true;
  bool close = false;  // ok, but within kCloseShare of failing
};

struct DiffReport {
  std::vector<LayerDiff> layers;  // pipeline order; the oracle's layers, then the port's extra ones
  bool ok = true;
  std::optional<FramePass> firstFailingPass;
};

// Compares `port` with `oracle`, the layers on all threads (core/parallel.h) in fixed bands of rows
// whose partial results are combined in band order: the report does not depend on the thread
// count. Layers the port lacks are listed as not compared (a port may implement some passes only)
// and do not fail; a layer of another size or type fails. Without geometry, coverage layers are
// compared like the others. Only the samples of compared layers (and the oracle's
// "raster.triangle" with geometry) are read: the oracle's file may be read with
// OracleLayersToRead(port).
DiffReport DiffDumps(const ExrFile& oracle, const ExrFile& port, const DiffThresholds& thresholds,
                     const std::optional<CoverageGeometry>& geometry);

// The light's view the two files' shadow maps were rasterized from, which judges their coverage
// (CoverageGeometry::shadowView): fitted as the shadow pass fits it to the oracle's G-buffer word 2,
// or to the port's where the oracle's file has none (`ssgi passes` on the port's buffers writes
// none: it ran on the port's); nothing where either file lacks a shadow map or no light casts
// shadows.
std::optional<ViewProjection> DiffShadowView(const ExrFile& oracle, const ExrFile& port, const Scene& scene,
                                             const FrameConfig& config);

// The channels of the oracle's dump DiffDumps reads against `port`: those the port also holds,
// the visibility buffer's triangle index, from which coverage differences are judged, and word 2
// where the port holds a shadow map (the light's view is fitted to it).
ExrChannelFilter OracleLayersToRead(const ExrFile& port);

// The per-pixel difference of one layer of both files as an 8-bit RGB heat map (black = equal,
// white = the largest difference), or an empty vector when the layer is not in both at one size.
std::vector<uint8_t> LayerDiffHeatmap(const ExrFile& oracle, const ExrFile& port, const std::string& layerId,
                                      int& width, int& height);

// The report as JSON text: {"ok", "firstFailingPass", "layers": [{"id", "pass", "ok", ...}]}.
std::string DiffReportJson(const DiffReport& report);

}  // namespace ssgi
