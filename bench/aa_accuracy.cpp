// The anti-aliasing's accuracy against a box-filtered truth (README "Anti-aliasing"): each --aa
// setting, with specular anti-aliasing off (--specular-aa 0) and on (the scene's kappa, or
// kSpecularAaKappa where the scene leaves it off), rendered at the scene's size. The error is the RMSE
// of the linear HDR image and of x / (1 + x) (what the eye sees, roughly) over the whole image and over
// masks of one kind of edge each (core/edge_masks.h). Two truths:
//
//   ssgi_aa_accuracy SCENE.json [SIZE] [CROP_PREFIX X Y SIDE]
//
// ssgi at 4x4 the size with both anti-aliasings off (its 16 samples per pixel see the edges and the
// normal's spread themselves), box-downsampled: the truth of geometric edges and highlights. Masks:
// the edge mask (the pairs of 4-neighbours across a geometric edge, GeometricEdge, of the frame
// without anti-aliasing, as PairMask) and the highlight mask (the pixels where the truth or the frame
// without either anti-aliasing has a channel above 1, dilated by one pixel: the highlights and their
// sparkles). With CROP_PREFIX, writes each setting's and the truth's tonemapped crop (SIDE pixels
// square at X, Y, scaled 8x by pixel replication) as CROP_PREFIX-<aa>-specular-<on|off>.png.
//
//   ssgi_aa_accuracy SCENE.json SIZE --reference REFERENCE.exr [--second-seed REFERENCE2.exr]
//                    [--point-sampled POINT.exr] [SETTING=VALUE ...]
//
// `ssgi reference --transport paper --background 0,0,0` at k times SIZE, box-downsampled k x k: the
// light the frame models, sampled on a regular k x k grid of each pixel. Not ssgi at a larger size:
// the shadow map's texels per pixel, the shadow blur's radius in pixels and the trace's fades all
// change with the size, so a larger frame has other shadow edges and reflections. The frame renders
// with the sky light and the bounce off and a black environment, as the reference: under a sky, the
// frame's background is the sky's mean radiance and its reflections without the sky light see no sky,
// where the reference's rays see the sky along each direction, a difference over the whole image that
// is no edge's. Masks: geometric edges (as above), shadow
// edges (ShadowEdgeMask of the reference's light visibility and direct light) and reflection edges
// (ReflectionEdgeMask of its direct and indirect light, on the pixels the trace reflects). Extra
// rows: with a reference of another seed, the reference's own noise (their RMSE over sqrt(2)); with
// one at SIZE (through the pixel centres, the paper transport's only primary rays), the error of
// point sampling alone: the aliasing of a frame whose shading were exact. SETTING=VALUE overrides a
// frame setting (passes/frame/config.h), such as shadow_map_size=4096.
//
// Prints one row per setting and each mask's error as a ratio to --aa off's. With SSGI_AA_MASKS=PNG
// set, writes the tonemapped truth, darkened, with the first mask in blue, the second in red, the third
// in green; with SSGI_AA_ERRORMAP=PREFIX, each setting's display error x 4 as
// PREFIX-<aa>-specular-<on|off>.png, the first mask a floor of blue.
// Times are BM_Table1Frame's (bench/plan_bench.cpp), not this tool's.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "core/edge_masks.h"
#include "core/error.h"
#include "core/image_compare.h"
#include "core/image_io.h"
#include "core/scene.h"
#include "passes/frame/config.h"
#include "passes/frame/frame.h"

namespace ssgi {
namespace {

struct Error {
  double rmse = 0.0, rmseDisplay = 0.0;
};

// The RMSE of a against truth (both interleaved RGB) over the pixels where mask is non-zero (every
// pixel when mask is empty).
Error Rmse(const std::vector<float>& a, const std::vector<float>& truth, const std::vector<uint8_t>& mask) {
  double sum = 0.0, sumDisplay = 0.0;
  size_t count = 0;
  for (size_t i = 0; i < a.size() / 3; ++i) {
    if (!mask.empty() && !mask[i]) continue;
    ++count;
    for (size_t c = 0; c < 3; ++c) {
      const double p = a[3 * i + c], t = truth[3 * i + c];
      sum += (p - t) * (p - t);
      const double pd = p / (1.0 + p), td = t / (1.0 + t);
      sumDisplay += (pd - td) * (pd - td);
    }
  }
  const double n = double(count == 0 ? 1 : count) * 3.0;
  return {std::sqrt(sum / n), std::sqrt(sumDisplay / n)};
}

// The pairs of 4-neighbours of a frame across a geometric edge.
NeighbourPairs GeometricEdgePairs(const Scene& scene, const Frame& frame) {
  const int width = frame.gbuffer.gbuffer.width(), height = frame.gbuffer.gbuffer.height();
  const VisibilityBuffer& v = frame.gbuffer.visibility;
  const Plane<uint32_t>& depth = frame.gbuffer.gbuffer.word[GBufferWord::kDepth];
  NeighbourPairs pairs{width, height, std::vector<uint8_t>(size_t(width) * size_t(height), 0)};
  const auto edgeBetween = [&](int x0, int y0, int x1, int y1) {
    return GeometricEdge(v.triangle.ConstRow(size_t(y0))[x0], v.triangle.ConstRow(size_t(y1))[x1],
                         UnpackDepth(depth.ConstRow(size_t(y0))[x0]), UnpackDepth(depth.ConstRow(size_t(y1))[x1]),
                         scene.mesh.materials.data());
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      uint8_t& bits = pairs.bits[size_t(y) * size_t(width) + size_t(x)];
      if (x + 1 < width && edgeBetween(x, y, x + 1, y)) bits |= kPairRight;
      if (y + 1 < height && edgeBetween(x, y, x, y + 1)) bits |= kPairDown;
    }
  return pairs;
}

// The pixels the trace reflects: geometry smoother than its cut-off.
std::vector<uint8_t> ReflectivePixels(const Frame& frame, float roughnessCutoff) {
  const GBuffer& g = frame.gbuffer.gbuffer;
  std::vector<uint8_t> reflective(size_t(g.width()) * size_t(g.height()), 0);
  for (int y = 0; y < g.height(); ++y)
    for (int x = 0; x < g.width(); ++x)
      reflective[size_t(y) * size_t(g.width()) + size_t(x)] =
          UnpackDepth(g.word[GBufferWord::kDepth].ConstRow(size_t(y))[x]) < kBackgroundDepth &&
          UnpackRoughness(g.word[GBufferWord::kNormalRoughness].ConstRow(size_t(y))[x]) < roughnessCutoff;
  return reflective;
}

// The highlight mask: pixels where a channel of the truth or of `image` (both interleaved) is above 1,
// dilated.
std::vector<uint8_t> HighlightMask(const std::vector<float>& truth, const std::vector<float>& image, int size) {
  std::vector<uint8_t> bright(truth.size() / 3, 0);
  for (size_t i = 0; i < bright.size(); ++i)
    for (size_t c = 0; c < 3; ++c) bright[i] |= truth[3 * i + c] > 1.0f || image[3 * i + c] > 1.0f;
  return DilatedMask(bright, size, size);
}

// The 8-bit tonemapped codes of the interleaved linear image's side x side square at x0, y0.
std::vector<uint8_t> Tonemapped(const std::vector<float>& rgb, int width, const FrameConfig& config, int x0, int y0,
                                int side) {
  Plane3<float> crop = MakePlane3<float>(size_t(side), size_t(side), 0.0f);
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x)
      for (int c = 0; c < 3; ++c)
        crop.c[c].MutableRow(size_t(y))[x] = rgb[(size_t(y0 + y) * size_t(width) + size_t(x0 + x)) * 3 + size_t(c)];
  TonemapOutputs out;
  RunTonemap(crop, config.tonemap, out);
  return out.rgb;
}

// Writes the tonemapped crop of an interleaved linear image, each pixel `zoom` x `zoom`.
void WriteCrop(const std::string& path, const std::vector<float>& rgb, int width, const FrameConfig& config, int x0,
               int y0, int side, int zoom) {
  const std::vector<uint8_t> codes = Tonemapped(rgb, width, config, x0, y0, side);
  std::vector<uint8_t> zoomed(size_t(side * zoom) * size_t(side * zoom) * 3);
  for (int y = 0; y < side * zoom; ++y)
    for (int x = 0; x < side * zoom; ++x)
      for (int c = 0; c < 3; ++c)
        zoomed[(size_t(y) * size_t(side * zoom) + size_t(x)) * 3 + size_t(c)] =
            codes[(size_t(y / zoom) * size_t(side) + size_t(x / zoom)) * 3 + size_t(c)];
  WritePng(path, side * zoom, side * zoom, zoomed);
}

std::vector<float> Interleaved(const Plane3<float>& image) {
  const size_t width = image.c[0].xsize(), height = image.c[0].ysize();
  std::vector<float> rgb(width * height * 3);
  for (size_t y = 0; y < height; ++y)
    for (size_t x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) rgb[(y * width + x) * 3 + size_t(c)] = image.c[c].ConstRow(y)[x];
  return rgb;
}

struct NamedMask {
  std::string name;
  std::vector<uint8_t> mask;
};

// What the settings are measured against: the truth (interleaved linear RGB at the frame's size) and
// the masks, made from the first frame (without either anti-aliasing).
struct Truth {
  std::vector<float> rgb;
  std::function<std::vector<NamedMask>(const Frame& first)> masks;
  std::vector<float> secondSeed;    // another reference's rgb, for its noise; empty without
  std::vector<float> pointSampled;  // the reference through the pixel centres; empty without
};

// ssgi at 4x4 the size, both anti-aliasings off, box-downsampled.
Truth SupersampledTruth(const SceneFile& file, const FrameConfig& config) {
  const int size = config.width;
  FrameConfig big = config;
  big.width = big.height = 4 * size;
  big.antialiasing = Antialiasing::kOff;
  big.specularAaKappa = 0.0f;
  Truth truth;
  {
    const Frame frame = RenderFrame(file.scene, big, BufferLifetime::kUntilLastReader);
    FloatImage image{big.width, big.height, {"R", "G", "B"}, Interleaved(frame.Result())};
    truth.rgb = BoxDownsampled(image, 4).pixels;
  }
  truth.masks = [&file, size, rgb = truth.rgb](const Frame& first) {
    return std::vector<NamedMask>{{"edge", PairMask(GeometricEdgePairs(file.scene, first))},
                                  {"hl", HighlightMask(rgb, Interleaved(first.Result()), size)}};
  };
  return truth;
}

// The reference's layer, box-downsampled to `size`.
FloatImage ReferenceLayer(const FloatImage& reference, const std::string& layer, const std::string& path, int size) {
  if (reference.width % size != 0 || reference.width != reference.height)
    throw InputError(path, "is " + std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                               ": give a square reference whose side is a multiple of " + std::to_string(size));
  return BoxDownsampled(SelectLayer(reference, layer, path), reference.width / size);
}

// `ssgi reference --transport paper --background 0,0,0` at a multiple of the size, box-downsampled.
Truth ReferenceTruth(const SceneFile& file, const FrameConfig& config, const std::string& path,
                     const std::string& secondSeedPath, const std::string& pointSampledPath) {
  const int size = config.width;
  const FloatImage reference = ReadFloatImage(path);
  const FloatImage rgb = SelectLayer(reference, "", path), depth = SelectLayer(reference, "depth", path);
  for (size_t i = 0; i < depth.pixels.size(); ++i)
    if (depth.pixels[i] == kBackgroundDepth &&
        (rgb.pixels[3 * i] != 0.0f || rgb.pixels[3 * i + 1] != 0.0f || rgb.pixels[3 * i + 2] != 0.0f))
      throw InputError(path, "has a background that is not black: render it with --background 0,0,0");
  Truth truth;
  truth.rgb = ReferenceLayer(reference, "", path, size).pixels;
  if (!secondSeedPath.empty())
    truth.secondSeed = ReferenceLayer(ReadFloatImage(secondSeedPath), "", secondSeedPath, size).pixels;
  if (!pointSampledPath.empty()) {
    const FloatImage point = SelectLayer(ReadFloatImage(pointSampledPath), "", pointSampledPath);
    if (point.width != size || point.height != size)
      throw InputError(pointSampledPath, "is not " + std::to_string(size) + "x" + std::to_string(size));
    truth.pointSampled = point.pixels;
  }
  const FloatImage visibility = ReferenceLayer(reference, "shadow.visibility", path, size);
  const FloatImage direct = ReferenceLayer(reference, "direct", path, size);
  const FloatImage indirect = ReferenceLayer(reference, "indirect", path, size);
  const float cutoff = config.ssrTrace.roughnessCutoff;
  truth.masks = [&file, visibility, direct, indirect, cutoff](const Frame& first) {
    const NeighbourPairs geometric = GeometricEdgePairs(file.scene, first);
    return std::vector<NamedMask>{
        {"geom", PairMask(geometric)},
        {"shadow", ShadowEdgeMask(visibility, direct, geometric)},
        {"refl", ReflectionEdgeMask(direct, indirect, ReflectivePixels(first, cutoff), geometric)}};
  };
  return truth;
}

// The truth, tonemapped and darkened, with the masks in blue, red and green.
void WriteMasks(const std::string& path, const Truth& truth, const std::vector<NamedMask>& masks, int size,
                const FrameConfig& config) {
  std::vector<uint8_t> image = Tonemapped(truth.rgb, size, config, 0, 0, size);
  for (uint8_t& code : image) code = uint8_t(code / 3);
  const size_t channelOfMask[] = {2, 0, 1};
  for (size_t m = 0; m < masks.size() && m < 3; ++m)
    for (size_t i = 0; i < masks[m].mask.size(); ++i)
      if (masks[m].mask[i]) image[3 * i + channelOfMask[m]] = 255;
  WritePng(path, size, size, image);
}

void WriteErrorMap(const std::string& path, const std::vector<float>& image, const std::vector<float>& truth,
                   const std::vector<uint8_t>& floor, int size) {
  std::vector<uint8_t> map(image.size(), 0);
  for (size_t i = 0; i < image.size(); ++i) {
    const double p = image[i], t = truth[i];
    map[i] = uint8_t(std::min(255.0, std::abs(p / (1 + p) - t / (1 + t)) * 4.0 * 255.0));
    if (i % 3 == 2 && floor[i / 3]) map[i] = std::max<uint8_t>(map[i], 40);
  }
  WritePng(path, size, size, map);
}

int Run(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: ssgi_aa_accuracy SCENE.json [SIZE] [CROP_PREFIX X Y SIDE]\n"
                 "       ssgi_aa_accuracy SCENE.json SIZE --reference REFERENCE.exr [--second-seed REFERENCE2.exr] "
                 "[--point-sampled POINT.exr] [SETTING=VALUE ...]\n");
    return 2;
  }
  const SceneFile file = LoadSceneFile(argv[1]);
  FrameConfig config = FrameConfigFromSceneFile(file);
  const int size = argc > 2 ? std::stoi(argv[2]) : 1024;
  config.width = config.height = size;
  const bool againstReference = argc > 3 && std::string(argv[3]) == "--reference";
  const bool crops = !againstReference && argc > 6;
  Truth truth;
  if (againstReference) {
    if (argc < 5) throw InputError("--reference needs a file");
    // The light the paper transport traces, under the black sky the reference was rendered with.
    ApplySetting(config, "effects.sky", "off");
    ApplySetting(config, "effects.bounce", "off");
    ApplySetting(config, "background", "0,0,0");
    std::string secondSeed, pointSampled;
    for (int i = 5; i < argc; ++i) {
      const std::string argument = argv[i];
      const size_t equals = argument.find('=');
      if ((argument == "--second-seed" || argument == "--point-sampled") && i + 1 < argc)
        (argument == "--second-seed" ? secondSeed : pointSampled) = argv[++i];
      else if (equals != std::string::npos)
        ApplySetting(config, argument.substr(0, equals), argument.substr(equals + 1));
      else
        throw InputError("unknown argument '" + argument + "'");
    }
    truth = ReferenceTruth(file, config, argv[4], secondSeed, pointSampled);
  } else {
    truth = SupersampledTruth(file, config);
  }
  const int cropX = crops ? std::stoi(argv[4]) : 0, cropY = crops ? std::stoi(argv[5]) : 0,
            cropSide = crops ? std::stoi(argv[6]) : 0;
  if (crops) WriteCrop(std::string(argv[3]) + "-truth.png", truth.rgb, size, config, cropX, cropY, cropSide, 8);

  std::vector<NamedMask> masks;
  struct Row {
    std::string name;
    std::vector<Error> errors;  // per mask, then the whole image
  };
  std::vector<Row> rows;
  const auto printRow = [&](const Row& row) {
    std::printf("%-18s", row.name.c_str());
    for (const Error& e : row.errors) std::printf(" %10.6f %10.6f", e.rmse, e.rmseDisplay);
    std::printf("\n");
  };
  const FrameSetting* setting = FindFrameSetting("antialiasing");
  const float specularKappa = config.specularAaKappa > 0.0f ? config.specularAaKappa : kSpecularAaKappa;
  for (std::string_view choice : setting->choices) {
    for (const float kappa : {0.0f, specularKappa}) {
      ApplySetting(config, "antialiasing", choice);
      config.specularAaKappa = kappa;
      const Frame frame = RenderFrame(file.scene, config, BufferLifetime::kKeepAll);
      const std::vector<float> image = Interleaved(frame.Result());
      if (masks.empty()) {
        masks = truth.masks(frame);
        std::printf("%-18s", "mask pixels:");
        for (const NamedMask& m : masks)
          std::printf(" %s %zu", m.name.c_str(), size_t(std::count(m.mask.begin(), m.mask.end(), uint8_t(1))));
        std::printf("\n%-18s", "setting");
        for (const NamedMask& m : masks)
          std::printf(" %10s %10s", (m.name + " rmse").c_str(), (m.name + " disp").c_str());
        std::printf(" %10s %10s\n", "whole rmse", "whole disp");
        const auto referenceRow = [&](const char* name, const std::vector<float>& other, double scale) {
          if (other.empty()) return;
          Row row{name, {}};
          for (const NamedMask& m : masks) row.errors.push_back(Rmse(other, truth.rgb, m.mask));
          row.errors.push_back(Rmse(other, truth.rgb, {}));
          for (Error& e : row.errors) e = {e.rmse * scale, e.rmseDisplay * scale};
          printRow(row);
        };
        referenceRow("reference noise", truth.secondSeed, 1.0 / std::sqrt(2.0));
        referenceRow("point-sampled", truth.pointSampled, 1.0);
        if (const char* path = std::getenv("SSGI_AA_MASKS")) WriteMasks(path, truth, masks, size, config);
      }
      const std::string name = std::string(choice) + (kappa > 0.0f ? "-specular-on" : "-specular-off");
      Row row{name, {}};
      for (const NamedMask& m : masks) row.errors.push_back(Rmse(image, truth.rgb, m.mask));
      row.errors.push_back(Rmse(image, truth.rgb, {}));
      printRow(row);
      rows.push_back(row);
      if (const char* prefix = std::getenv("SSGI_AA_ERRORMAP"))
        WriteErrorMap(std::string(prefix) + "-" + name + ".png", image, truth.rgb, masks[0].mask, size);
      if (crops) WriteCrop(std::string(argv[3]) + "-" + name + ".png", image, size, config, cropX, cropY, cropSide, 8);
    }
  }
  // Each row's errors over those of --aa off with the same specular anti-aliasing (rows 0 and 1).
  std::printf("\nratio to --aa off\n");
  for (size_t r = 0; r < rows.size(); ++r) {
    Row ratio{rows[r].name, {}};
    for (size_t e = 0; e < rows[r].errors.size(); ++e) {
      const Error& off = rows[r % 2].errors[e];
      ratio.errors.push_back({rows[r].errors[e].rmse / off.rmse, rows[r].errors[e].rmseDisplay / off.rmseDisplay});
    }
    printRow(ratio);
  }
  return 0;
}

}  // namespace
}  // namespace ssgi

int main(int argc, char** argv) {
  try {
    return ssgi::Run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ssgi_aa_accuracy: error: %s\n", e.what());
    return 1;
  }
}
