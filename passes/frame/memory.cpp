// The frame's memory: estimate, and what the system has.
#include "passes/frame/memory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <fstream>

#include "core/error.h"
#include "core/plane.h"
#include "passes/frame/dump.h"
#include "passes/frame/registry.h"
#include "passes/shadow_map.h"

namespace ssgi {
namespace {

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
  const bool release = lifetime == BufferLifetime::kUntilLastReader;
  const FrameShape shape{size_t(config.width), size_t(config.height), scene.mesh.TriangleCount(),
                         size_t(config.shadowMap.resolution), release};
  const auto mayRun = [&](FrameEffect effect) {
    switch (effect) {
      case FrameEffect::kAlways:
        return true;
      case FrameEffect::kShadows:
        return config.shadows != EffectMode::kOff && !ShadowCastingLights(scene).empty();
      case FrameEffect::kReflections:
        return config.reflections != EffectMode::kOff;
    }
    return false;
  };
  const size_t lastStep = FrameSteps().size() - 1;
  FrameMemoryEstimate estimate;
  for (const PassDeclaration& pass : FramePasses()) {
    if (!mayRun(pass.effect)) continue;
    const size_t step = StepOf(pass.pass);
    for (const BufferDeclaration& buffer : pass.makes) {
      const size_t end = release ? LastStepOf(buffer.id).value_or(lastStep) : lastStep;
      estimate.buffers.push_back({std::string(buffer.name), buffer.bytes(shape), step, end});
    }
    if (pass.scratchBytes)
      estimate.buffers.push_back({std::string(pass.scratchName), pass.scratchBytes(shape), step, step});
  }
  if (dumped) {
    // The dump's decoded layers and the display image's codes, as uint32 planes, while it is written.
    size_t decoded = 0;
    for (const DumpLayer& layer : DumpLayers()) decoded += layer.decoded ? 1 : 0;
    estimate.buffers.push_back({"dump's decoded layers",
                                decoded * hwy::ImageBase::BytesPerRow(shape.width, 4) * shape.height, lastStep,
                                lastStep});
  }
  for (size_t step = 0; step <= lastStep; ++step) {
    size_t alive = 0;
    for (const FrameMemoryEstimate::Buffer& buffer : estimate.buffers)
      if (buffer.madeStep <= step && step <= buffer.endStep) alive += buffer.bytes;
    estimate.stepBytes.push_back(alive);
    if (alive > estimate.bytes) {
      estimate.bytes = alive;
      estimate.peakPass = FrameSteps()[step];
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
