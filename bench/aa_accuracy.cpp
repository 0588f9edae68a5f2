// The anti-aliasing's accuracy against a supersampled truth (docs/pipeline.md §Anti-aliasing):
// each --aa setting, with specular anti-aliasing off (--specular-aa 0) and on (the scene's kappa, or
// kSpecularAaKappa where the scene leaves it off),
// rendered at the scene's size, against ssgi at 4x4 the size with both off (its 16 samples per pixel
// see the edges and the normal's spread themselves), box-downsampled. The error is the RMSE of the
// linear HDR image and of x / (1 + x) (what the eye sees, roughly) over the whole image, over the
// edge mask (the pixels next to a geometric edge, GeometricEdge between 4-neighbours of the frame
// without anti-aliasing, dilated by one pixel) and over the highlight mask (the pixels where the
// truth or the frame without either anti-aliasing has a channel above 1, dilated by one pixel: the
// highlights and their sparkles).
// Times are BM_Table1Frame's (bench/plan_bench.cpp), not this tool's.
//   ssgi_aa_accuracy SCENE.json [SIZE] [CROP_PREFIX X Y SIDE]
// prints one row per setting; with CROP_PREFIX, writes each setting's and the truth's tonemapped
// crop (SIDE pixels square at X, Y, scaled 8x by pixel replication) as
// CROP_PREFIX-<aa>-specular-<on|off>.png. With SSGI_AA_ERRORMAP=PREFIX set, also each setting's display
// error x 4 as PREFIX-<aa>-specular-<on|off>.png, the edge mask a floor of blue.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/image_io.h"
#include "core/scene.h"
#include "passes/frame/config.h"
#include "passes/frame/frame.h"

namespace ssgi {
namespace {

struct Error {
  double rmse = 0.0, rmseDisplay = 0.0;
};

// The RMSE of a against b over the pixels where mask is non-zero (every pixel when mask is empty).
Error Rmse(const Plane3<float>& a, const std::vector<float>& truth, const std::vector<uint8_t>& mask) {
  const size_t width = a.c[0].xsize(), height = a.c[0].ysize();
  double sum = 0.0, sumDisplay = 0.0;
  size_t count = 0;
  for (size_t y = 0; y < height; ++y)
    for (size_t x = 0; x < width; ++x) {
      if (!mask.empty() && !mask[y * width + x]) continue;
      ++count;
      for (int c = 0; c < 3; ++c) {
        const double p = a.c[c].ConstRow(y)[x], t = truth[(y * width + x) * 3 + size_t(c)];
        sum += (p - t) * (p - t);
        const double pd = p / (1.0 + p), td = t / (1.0 + t);
        sumDisplay += (pd - td) * (pd - td);
      }
    }
  const double n = double(count == 0 ? 1 : count) * 3.0;
  return {std::sqrt(sum / n), std::sqrt(sumDisplay / n)};
}

// The pixels of `marked` (width x height) and their 8 neighbours.
std::vector<uint8_t> Dilated(const std::vector<uint8_t>& marked, int width, int height) {
  std::vector<uint8_t> mask(marked.size(), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int sx = x + dx, sy = y + dy;
          if (sx >= 0 && sy >= 0 && sx < width && sy < height && marked[size_t(sy) * width + sx])
            mask[size_t(y) * width + x] = 1;
        }
  return mask;
}

// The edge mask of a frame: pixels with a 4-neighbour across a geometric edge, dilated by one pixel
// (3x3).
std::vector<uint8_t> EdgeMask(const Scene& scene, const Frame& frame) {
  const int width = frame.gbuffer.gbuffer.width(), height = frame.gbuffer.gbuffer.height();
  const VisibilityBuffer& v = frame.gbuffer.visibility;
  const Plane<uint32_t>& depth = frame.gbuffer.gbuffer.word[GBufferWord::kDepth];
  std::vector<uint8_t> edge(size_t(width) * size_t(height), 0);
  const auto edgeBetween = [&](int x0, int y0, int x1, int y1) {
    return GeometricEdge(v.triangle.ConstRow(size_t(y0))[x0], v.triangle.ConstRow(size_t(y1))[x1],
                         UnpackDepth(depth.ConstRow(size_t(y0))[x0]), UnpackDepth(depth.ConstRow(size_t(y1))[x1]),
                         scene.mesh.materials.data());
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      if (x + 1 < width && edgeBetween(x, y, x + 1, y))
        edge[size_t(y) * width + x] = edge[size_t(y) * width + x + 1] = 1;
      if (y + 1 < height && edgeBetween(x, y, x, y + 1))
        edge[size_t(y) * width + x] = edge[size_t(y + 1) * width + x] = 1;
    }
  return Dilated(edge, width, height);
}

// The highlight mask: pixels where a channel of the truth (interleaved) or of `image` is above 1,
// dilated.
std::vector<uint8_t> HighlightMask(const std::vector<float>& truth, const Plane3<float>& image) {
  const int width = int(image.c[0].xsize()), height = int(image.c[0].ysize());
  std::vector<uint8_t> bright(size_t(width) * size_t(height), 0);
  for (size_t y = 0; y < size_t(height); ++y)
    for (size_t x = 0; x < size_t(width); ++x) {
      const size_t i = y * size_t(width) + x;
      for (int c = 0; c < 3; ++c)
        bright[i] |= truth[3 * i + size_t(c)] > 1.0f || image.c[c].ConstRow(y)[x] > 1.0f;
    }
  return Dilated(bright, width, height);
}

// Writes the tonemapped crop of an interleaved linear image, each pixel `zoom` x `zoom`.
void WriteCrop(const std::string& path, const std::vector<float>& rgb, int width, const FrameConfig& config, int x0,
               int y0, int side, int zoom) {
  Plane3<float> crop = MakePlane3<float>(size_t(side), size_t(side), 0.0f);
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x)
      for (int c = 0; c < 3; ++c)
        crop.c[c].MutableRow(size_t(y))[x] = rgb[(size_t(y0 + y) * size_t(width) + size_t(x0 + x)) * 3 + size_t(c)];
  TonemapOutputs out;
  RunTonemap(crop, config.tonemap, out);
  std::vector<uint8_t> zoomed(size_t(side * zoom) * size_t(side * zoom) * 3);
  for (int y = 0; y < side * zoom; ++y)
    for (int x = 0; x < side * zoom; ++x)
      for (int c = 0; c < 3; ++c)
        zoomed[(size_t(y) * size_t(side * zoom) + size_t(x)) * 3 + size_t(c)] =
            out.rgb[(size_t(y / zoom) * size_t(side) + size_t(x / zoom)) * 3 + size_t(c)];
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

int Run(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: ssgi_aa_accuracy SCENE.json [SIZE] [CROP_PREFIX X Y SIDE]\n");
    return 2;
  }
  const SceneFile file = LoadSceneFile(argv[1]);
  FrameConfig config = FrameConfigFromSceneFile(file);
  const int size = argc > 2 ? std::stoi(argv[2]) : 1024;
  config.width = config.height = size;
  // The truth: 4x4 the size, anti-aliasing off, each 4x4 block's mean.
  FrameConfig big = config;
  big.width = big.height = 4 * size;
  big.antialiasing = Antialiasing::kOff;
  big.specularAaKappa = 0.0f;
  std::vector<float> truth(size_t(size) * size_t(size) * 3, 0.0f);
  {
    const Frame frame = RenderFrame(file.scene, big, BufferLifetime::kUntilLastReader);
    const Plane3<float>& image = frame.Result();
    for (int y = 0; y < 4 * size; ++y)
      for (int x = 0; x < 4 * size; ++x)
        for (int c = 0; c < 3; ++c)
          truth[(size_t(y / 4) * size_t(size) + size_t(x / 4)) * 3 + size_t(c)] +=
              image.c[c].ConstRow(size_t(y))[x] * (1.0f / 16.0f);
  }
  const bool crops = argc > 6;
  const int cropX = crops ? std::stoi(argv[4]) : 0, cropY = crops ? std::stoi(argv[5]) : 0,
            cropSide = crops ? std::stoi(argv[6]) : 0;
  if (crops) WriteCrop(std::string(argv[3]) + "-truth.png", truth, size, config, cropX, cropY, cropSide, 8);
  std::vector<uint8_t> mask, highlights;
  std::printf("%-6s %-9s %10s %10s %10s %10s %10s %10s %8s %8s\n", "aa", "specular", "edge rmse", "edge disp",
              "hl rmse", "hl disp", "whole rmse", "whole disp", "edge px", "hl px");
  const FrameSetting* setting = FindFrameSetting("antialiasing");
  const float specularKappa = config.specularAaKappa > 0.0f ? config.specularAaKappa : kSpecularAaKappa;
  for (std::string_view choice : setting->choices) {
    for (const float kappa : {0.0f, specularKappa}) {
      ApplySetting(config, "antialiasing", choice);
      config.specularAaKappa = kappa;
      const Frame frame = RenderFrame(file.scene, config, BufferLifetime::kKeepAll);
      if (mask.empty()) mask = EdgeMask(file.scene, frame);
      if (highlights.empty()) highlights = HighlightMask(truth, frame.Result());
      size_t masked = 0, highlighted = 0;
      for (uint8_t m : mask) masked += m;
      for (uint8_t m : highlights) highlighted += m;
      const Error edge = Rmse(frame.Result(), truth, mask), whole = Rmse(frame.Result(), truth, {});
      const Error highlight = Rmse(frame.Result(), truth, highlights);
      const std::string name = std::string(choice) + (kappa > 0.0f ? "-specular-on" : "-specular-off");
      std::printf("%-6s %-9s %10.6f %10.6f %10.6f %10.6f %10.6f %10.6f %8zu %8zu\n", std::string(choice).c_str(),
                  kappa > 0.0f ? "on" : "off", edge.rmse, edge.rmseDisplay, highlight.rmse, highlight.rmseDisplay,
                  whole.rmse, whole.rmseDisplay, masked, highlighted);
      if (std::getenv("SSGI_AA_ERRORMAP")) {
        const size_t w = size_t(size);
        std::vector<uint8_t> map(w * w * 3, 0);
        for (size_t y = 0; y < w; ++y)
          for (size_t x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
              const double p = frame.Result().c[c].ConstRow(y)[x], t = truth[(y * w + x) * 3 + size_t(c)];
              const double e = std::abs(p / (1 + p) - t / (1 + t)) * 4.0 * 255.0;
              map[(y * w + x) * 3 + size_t(c)] = uint8_t(std::min(255.0, e));
              if (mask[y * w + x] && c == 2) map[(y * w + x) * 3 + 2] = std::max<uint8_t>(map[(y * w + x) * 3 + 2], 40);
            }
        WritePng(std::string(std::getenv("SSGI_AA_ERRORMAP")) + "-" + name + ".png", size, size, map);
      }
      if (crops)
        WriteCrop(std::string(argv[3]) + "-" + name + ".png", Interleaved(frame.Result()), size, config, cropX, cropY,
                  cropSide, 8);
    }
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
