// The frame's memory (docs/design.md §9): what its buffers take, estimated before any of them
// is allocated, so that a frame too large for the machine is refused with one clear line instead of
// ending in std::bad_alloc or the kernel's out-of-memory killer.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/scene.h"
#include "passes/frame/frame.h"
#include "passes/frame/config.h"

namespace ssgi {

struct FrameMemoryEstimate {
  struct Buffer {
    std::string name;
    size_t bytes = 0;
    // Alive from the step (FrameSteps) of the pass that makes it to the step after which it is freed
    // (the last step: kept to the frame's end).
    size_t madeStep = 0;
    size_t endStep = 0;
  };
  // Every buffer of the frame and each pass's scratch memory, for the effects that may run, as the
  // pass registry declares them (passes/frame/registry.h).
  std::vector<Buffer> buffers;
  std::vector<size_t> stepBytes;  // per step: the bytes alive during it
  size_t bytes = 0;               // the most alive at once: during the step where the sum peaks
  FramePass peakPass = FramePass::kGBuffer;
};

// The peak bytes of the buffers of a frame of this scene and configuration: every plane at its
// padded row size, the shadow map and the rasterizers' per-triangle set-up, counting every effect
// the scene and configuration allow (the frame plan may still skip some), each buffer alive from
// the step that makes it to the end (kKeepAll, kKeepForReuse) or until RunFramePasses frees it
// (kUntilLastReader: LastStepOf in passes/frame/registry.h). dumped: the frame is written as a dump
// at its end (WriteFrameDump's decoded layers counted too).
FrameMemoryEstimate EstimateFrameMemory(const Scene& scene, const FrameConfig& config, BufferLifetime lifetime,
                                        bool dumped = false);

}  // namespace ssgi
