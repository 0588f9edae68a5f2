// The frame's memory: estimate, and what the system has.
#include "passes/frame/memory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <fstream>

#include "core/error.h"
#include "core/plane.h"
#include "core/pyramid.h"
#include "passes/shadow_map.h"

namespace ssgi {
namespace {

// The bytes of a Plane<T> of that size: hwy::Image pads each row to its alignment and vector size.
template <class T>
size_t PlaneBytes(size_t width, size_t height) {
  return hwy::ImageBase::BytesPerRow(width, sizeof(T)) * height;
}

// What the rasterizer keeps per submitted triangle: the set-up triangle and its tile-bin entries.
constexpr size_t kRasterBytesPerTriangle = 160;

// Field `field` (0 the size, 1 the resident set, 2 its file-backed part: RssFile + RssShmem) of
// /proc/self/statm, in bytes; 0 where unknown.
size_t StatmBytes(int field) {
  std::ifstream statm("/proc/self/statm");
  size_t pages[3] = {};
  if (!(statm >> pages[0] >> pages[1] >> pages[2])) return 0;
  return pages[field] * size_t(::sysconf(_SC_PAGESIZE));
}

}  // namespace

FrameMemoryEstimate EstimateFrameMemory(const Scene& scene, const FrameConfig& config, BufferLifetime lifetime,
                                        bool dumped) {
  using P = FramePass;
  const size_t w = size_t(config.width), h = size_t(config.height);
  FrameMemoryEstimate estimate;
  const auto add = [&](std::string name, size_t bytes, P made, P lastRead) {
    estimate.buffers.push_back({std::move(name), bytes, made, lastRead});
  };
  const size_t floatPlane = PlaneBytes<float>(w, h);
  const size_t setUp = kRasterBytesPerTriangle * scene.mesh.TriangleCount();
  add("g-buffer words 0-2", 3 * floatPlane, P::kGBuffer, P::kTonemap);
  add("g-buffer word 3", floatPlane, P::kGBuffer, P::kShadowFilter);
  add("visibility buffer", 2 * floatPlane, P::kGBuffer, P::kGBuffer);
  add("g-buffer raster set-up", setUp, P::kGBuffer, P::kGBuffer);
  if (config.shadows != EffectMode::kOff && !ShadowCastingLights(scene).empty()) {
    const size_t side = size_t(config.shadowMap.resolution);
    add("shadow map", PlaneBytes<float>(side, side), P::kShadowMap, P::kShadowMap);  // depth keys only
    add("shadow-map raster set-up", setUp, P::kShadowMap, P::kShadowMap);
    add("shadow visibility", floatPlane, P::kShadowFilter, P::kDirectLight);
  }
  const bool reflections = config.reflections != EffectMode::kOff;
  // Freeing early, the frame hands buffers on instead of copying them (RunFramePasses): the direct
  // image is the pyramid's level 0 and then the result; the hits become the reflection's red and
  // green, and the reflection the indirect term.
  const bool handOver = lifetime == BufferLifetime::kUntilLastReader;
  add("direct light", 3 * floatPlane, P::kDirectLight, reflections && !handOver ? P::kComposite : P::kTonemap);
  if (reflections) {
    size_t hiz = 0, pyramid = 0;
    const std::vector<PyramidSize> levels = PyramidLevelSizes(w, h);
    for (size_t k = 0; k < levels.size(); ++k) {
      hiz += PlaneBytes<float>(levels[k].width, levels[k].height);
      if (k > 0 || !handOver) pyramid += 3 * PlaneBytes<float>(levels[k].width, levels[k].height);
    }
    add("hi-z", hiz, P::kHiZ, P::kSsrTrace);
    // Handing over, the frame makes the pyramid after the trace (RunFramePasses), when the Hi-Z is freed.
    add("colour pyramid", pyramid, handOver ? P::kSsrCone : P::kColorPyramid, P::kSsrCone);
    add("ssr hits", 2 * floatPlane, P::kSsrTrace, handOver ? P::kComposite : P::kSsrCone);
    if (!handOver) add("ssr steps", floatPlane, P::kSsrTrace, P::kSsrTrace);
    add("ssr confidence", floatPlane, P::kSsrTrace, P::kComposite);
    add("cone trace", (handOver ? 1 : 3) * floatPlane, P::kSsrCone, P::kComposite);
    if (!handOver) {
      add("indirect", 3 * floatPlane, P::kComposite, P::kComposite);
      add("result", 3 * floatPlane, P::kComposite, P::kTonemap);
    }
  }
  add("display image", w * h * 3, P::kTonemap, P::kTonemap);
  // The dump's decoded G-buffer and shadow-term layers (11) and 8-bit codes as uint32 (3).
  if (dumped) add("dump's decoded layers", 14 * floatPlane, P::kTonemap, P::kTonemap);
  for (FramePass pass : kFramePasses) {
    size_t alive = 0;
    for (const FrameMemoryEstimate::Buffer& buffer : estimate.buffers) {
      const FramePass end = lifetime == BufferLifetime::kUntilLastReader ? buffer.lastRead : P::kTonemap;
      if (buffer.made <= pass && pass <= end) alive += buffer.bytes;
    }
    if (alive > estimate.bytes) {
      estimate.bytes = alive;
      estimate.peakPass = pass;
    }
  }
  return estimate;
}

size_t AvailableMemoryBytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  size_t kib = 0;
  std::string unit;
  while (meminfo >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  return 0;
}

size_t ResidentBytes() { return StatmBytes(1); }

size_t ResidentFileBytes() { return StatmBytes(2); }

size_t PeakResidentBytes() {
  rusage usage{};
  if (::getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return size_t(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

std::string FormatBytes(size_t bytes) {
  char text[32];
  const double value = double(bytes);
  if (value >= 1024.0 * 1024.0 * 1024.0)
    std::snprintf(text, sizeof(text), "%.1f GiB", value / (1024.0 * 1024.0 * 1024.0));
  else
    std::snprintf(text, sizeof(text), "%.0f MiB", value / (1024.0 * 1024.0));
  return text;
}

size_t ParseByteCount(const std::string& text) {
  size_t digits = 0;
  while (digits < text.size() && std::isdigit(static_cast<unsigned char>(text[digits]))) ++digits;
  const std::string unit = text.substr(digits);
  double scale = 0.0;
  const char* const prefixes[] = {"", "K", "M", "G", "T"};
  for (size_t k = 0; k < 5; ++k) {
    const std::string p = prefixes[k];
    for (const std::string& spelling : {p, p + "B", p.empty() ? std::string("B") : p + "iB"})
      if (unit == spelling) scale = double(size_t(1) << (10 * k));
  }
  const double value = digits > 0 && digits <= 15 ? std::stod(text.substr(0, digits)) : 0.0;
  if (scale == 0.0 || !(value > 0.0)) throw InputError("--max-memory: must be a size like 512M or 8G, got '" + text + "'");
  return size_t(value * scale);
}

}  // namespace ssgi
