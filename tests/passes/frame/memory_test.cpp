// The frame's memory (passes/frame/memory.h): the estimate, derived from the pass registry, against
// what RunFramePasses holds at each step.
#include "passes/frame/memory.h"

#include <catch2/catch.hpp>

#include "passes/frame/registry.h"
#include "tests/passes/test_scenes.h"

namespace ssgi {
namespace {

// The bytes every buffer of the frame holds now.
size_t HeldBytes(const Frame& frame) {
  size_t bytes = 0;
  for (const MadeBuffer& made : FrameBuffers()) bytes += made.buffer->heldBytes(frame);
  return bytes;
}

// The estimate's bytes at each step less the passes' scratch memory, which the frame does not hold.
std::vector<size_t> EstimatedFrameBytes(const FrameMemoryEstimate& estimate) {
  std::vector<size_t> bytes = estimate.stepBytes;
  for (const PassDeclaration& pass : FramePasses()) {
    if (!pass.scratchBytes) continue;
    for (const FrameMemoryEstimate::Buffer& buffer : estimate.buffers)
      if (buffer.name == pass.scratchName) bytes[buffer.madeStep] -= buffer.bytes;
  }
  return bytes;
}

TEST_CASE("the memory estimate and the frame's release schedule agree, step by step", "[frame][memory]") {
  const test::DefaultScene defaults = test::LoadDefaultScene();
  // The bounce on, and in `auto`, where the interreflection volume stands for it and neither the
  // estimate nor the frame holds its buffers.
  for (const auto& [width, height, antialiasing, bounce] : {std::tuple{96, 64, Antialiasing::kEdge, EffectMode::kOn},
                                                            {67, 45, Antialiasing::kEdge, EffectMode::kOn},
                                                            {67, 45, Antialiasing::kMlaa, EffectMode::kOn},
                                                            {67, 45, Antialiasing::kEdge, EffectMode::kAuto}}) {
    FrameConfig config = defaults.config;
    config.width = width;
    config.height = height;
    config.shadowMap.resolution = 256;
    config.antialiasing = antialiasing;
    config.bounce = bounce;
    for (BufferLifetime lifetime : {BufferLifetime::kUntilLastReader, BufferLifetime::kKeepAll}) {
      CAPTURE(width, height, int(antialiasing), int(bounce), int(lifetime));
      const FrameMemoryEstimate estimate = EstimateFrameMemory(defaults.scene, config, lifetime);
      std::vector<size_t> held;
      Frame frame;
      RunFramePasses(defaults.scene, config, FramePass::kGBuffer, FramePass::kTonemap, frame, lifetime,
                     [&](FramePass, const Frame& f) { held.push_back(HeldBytes(f)); });
      // Every effect that may run runs on this scene, so the estimate's "may run" is what ran.
      REQUIRE(frame.shadows);
      REQUIRE(frame.reflections);
      REQUIRE(frame.sky);
      REQUIRE(frame.bounce == (bounce == EffectMode::kOn));
      const std::vector<size_t> estimated = EstimatedFrameBytes(estimate);
      REQUIRE(held.size() == FrameSteps().size());
      for (size_t step = 0; step < held.size(); ++step) {
        CAPTURE(FramePassName(FrameSteps()[step]));
        CHECK(held[step] == estimated[step]);
      }
      // The estimate's peak is its largest step.
      CHECK(estimate.bytes == *std::max_element(estimate.stepBytes.begin(), estimate.stepBytes.end()));
    }
  }
}

TEST_CASE("every buffer the frame frees early is freed after its last reader and no later", "[frame][memory]") {
  // A buffer freed at its last reader's step is gone at every later step; a frame output never goes.
  const test::DefaultScene defaults = test::LoadDefaultScene();
  FrameConfig config = defaults.config;
  config.width = 48;
  config.height = 32;
  config.shadowMap.resolution = 128;
  for (Antialiasing antialiasing : {Antialiasing::kEdge, Antialiasing::kMlaa}) {
    CAPTURE(int(antialiasing));
    config.antialiasing = antialiasing;
    std::vector<std::vector<size_t>> heldPerBuffer;
    Frame frame;
    RunFramePasses(defaults.scene, config, FramePass::kGBuffer, FramePass::kTonemap, frame,
                   BufferLifetime::kUntilLastReader, [&](FramePass, const Frame& f) {
                     std::vector<size_t> held;
                     for (const MadeBuffer& made : FrameBuffers()) held.push_back(made.buffer->heldBytes(f));
                     heldPerBuffer.push_back(held);
                   });
    for (const MadeBuffer& made : FrameBuffers()) {
      const BufferDeclaration& buffer = *made.buffer;
      CAPTURE(buffer.name);
      const std::optional<size_t> last = LastStepOf(buffer.id);
      CHECK(last.has_value() == (buffer.release != nullptr));
      for (size_t step = 0; step < heldPerBuffer.size(); ++step) {
        const size_t held = heldPerBuffer[step][size_t(buffer.id)];
        if (step < StepOf(made.maker->pass)) CHECK(held == 0);
        if (last && step > *last) CHECK(held == 0);
      }
      // After the frame only the outputs hold memory.
      CHECK((buffer.heldBytes(frame) > 0) == buffer.frameOutput);
    }
  }
}

}  // namespace
}  // namespace ssgi
