// The frame's memory (DESIGN.md §9, issue 14): what its buffers take, estimated before any of them
// is allocated, so that a frame too large for the machine is refused with one clear line instead of
// ending in std::bad_alloc or the kernel's out-of-memory killer.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/scene.h"
#include "passes/frame_config.h"

namespace ssgi {

struct FrameMemoryEstimate {
  struct Buffer {
    std::string name;
    size_t bytes = 0;
  };
  std::vector<Buffer> buffers;  // every buffer the frame keeps, for the effects that may run
  size_t bytes = 0;             // their sum
};

// The bytes of the buffers a frame of this scene and configuration keeps until it ends: every
// plane at its padded row size, the shadow map and the rasterizers' per-triangle set-up, counting
// every effect the scene and configuration allow (the frame plan may still skip some).
FrameMemoryEstimate EstimateFrameMemory(const Scene& scene, const FrameConfig& config);

// The memory the system could give this process now (MemAvailable of /proc/meminfo), or 0 where
// that is unknown.
size_t AvailableMemoryBytes();
// The process's resident set now and at its peak so far (Linux), in bytes; 0 where unknown.
size_t ResidentBytes();
size_t PeakResidentBytes();

// "1.5 GiB", "730 MiB": for messages.
std::string FormatBytes(size_t bytes);
// A byte count as given on a command line: digits with an optional K, M, G or T (powers of 1024,
// "B" or "iB" after it allowed), as --max-memory takes it. Throws InputError naming the option.
size_t ParseByteCount(const std::string& text);

}  // namespace ssgi
