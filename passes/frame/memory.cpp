// The frame's memory, estimated from the pass registry.
#include "passes/frame/memory.h"

#include <algorithm>

#include "core/plane.h"
#include "passes/frame/dump.h"
#include "passes/frame/registry.h"
#include "passes/shadow_map.h"

namespace ssgi {

FrameMemoryEstimate EstimateFrameMemory(const Scene& scene, const FrameConfig& config, BufferLifetime lifetime,
                                        bool dumped) {
  const bool release = lifetime == BufferLifetime::kUntilLastReader;
  FrameShape shape{size_t(config.width), size_t(config.height), scene.mesh.TriangleCount(),
                   size_t(config.shadowMap.resolution)};
  shape.vertices = scene.mesh.positions.size();
  shape.handOver = release;
  shape.edgeCoverage = config.antialiasing == Antialiasing::kEdge;
  shape.mlaa = config.antialiasing == Antialiasing::kMlaa;
  if (config.sky != EffectMode::kOff) {
    shape.interreflection = SkyMakesInterreflection(config);
    shape.skyVolumeBytes = SkyVisibilityBytes(scene, config.skyVisibility) +
                           WorldBounceBytes(scene, config.skyVisibility, config.interreflection);
    shape.skyVolumeBuildBytes = std::max(SkyVisibilityBuildBytes(scene, config.skyVisibility),
                                         WorldBounceBuildBytes(scene, config.skyVisibility, config.interreflection));
  }
  // In `auto`, the bounce does not run where the sky light makes the interreflection volume (the sky
  // light runs, in `auto`, where a pixel has geometry and the environment is not black or a light
  // reaches it).
  const bool skyMayRun = config.sky == EffectMode::kOn ||
                         (config.sky == EffectMode::kAuto &&
                          (!config.environment.IsBlack() || (scene.HasLights() && SkyMakesInterreflection(config))));
  const bool bounceMayRun = config.bounce == EffectMode::kOn ||
                            (config.bounce == EffectMode::kAuto && !(skyMayRun && SkyMakesInterreflection(config)));
  const auto mayRun = [&](FrameEffect effect) {
    switch (effect) {
      case FrameEffect::kAlways:
        return true;
      case FrameEffect::kShadows:
        return config.shadows != EffectMode::kOff && !ShadowCastingLights(scene).empty();
      case FrameEffect::kReflections:
        return config.reflections != EffectMode::kOff;
      case FrameEffect::kSky:
        return config.sky != EffectMode::kOff;
      case FrameEffect::kBounce:
        return bounceMayRun;
      case FrameEffect::kIndirect:
        return config.reflections != EffectMode::kOff || config.sky != EffectMode::kOff || bounceMayRun;
      case FrameEffect::kAntialias:
        return config.antialiasing != Antialiasing::kOff;
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

}  // namespace ssgi
