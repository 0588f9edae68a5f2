#include "passes/frame/frame.h"

#include <utility>

#include "core/error.h"
#include "core/stopwatch.h"

namespace ssgi {

std::string_view FramePassName(FramePass pass) { return FramePassDeclaration(pass).name; }

std::string FramePassNames() {
  std::string names;
  for (const PassDeclaration& pass : FramePasses()) names += (names.empty() ? "" : ", ") + std::string(pass.name);
  return names;
}

FramePass ParseFramePass(std::string_view name) {
  for (const PassDeclaration& pass : FramePasses())
    if (pass.name == name) return pass.pass;
  throw InputError("'" + std::string(name) + "' is not a pass; the passes: " + FramePassNames());
}

bool EffectBelongs(FrameEffect effect, bool shadows, bool reflections, bool sky, bool bounce, bool antialias) {
  switch (effect) {
    case FrameEffect::kAlways:
      return true;
    case FrameEffect::kShadows:
      return shadows;
    case FrameEffect::kReflections:
      return reflections;
    case FrameEffect::kSky:
      return sky;
    case FrameEffect::kBounce:
      return bounce;
    case FrameEffect::kIndirect:
      return reflections || sky || bounce;
    case FrameEffect::kAntialias:
      return antialias;
  }
  return false;
}

Frame RenderFrame(const Scene& scene, const FrameConfig& config, BufferLifetime lifetime) {
  Frame frame;
  RunFramePasses(scene, config, FramePass::kGBuffer, FramePass::kTonemap, frame, lifetime);
  return frame;
}

void RunFramePasses(const Scene& scene, const FrameConfig& config, FramePass from, FramePass to, Frame& frame,
                    BufferLifetime lifetime, const FrameStepObserver& observer) {
  FrameStats& stats = frame.stats;
  stats = FrameStats{};
  Stopwatch total;
  frame.view = MakePerspective(scene.camera, config.width, config.height);
  stats.triangles = scene.mesh.TriangleCount();
  stats.pixels = size_t(config.width) * size_t(config.height);
  FrameStep step{scene, config, frame, lifetime, from, to};
  // Frees, freeing early, the buffers whose last reader ran at this step.
  const auto release = [&](size_t index) {
    if (lifetime != BufferLifetime::kUntilLastReader) return;
    for (const MadeBuffer& made : FrameBuffers())
      if (made.buffer->release && LastStepOf(made.buffer->id) == index) made.buffer->release(frame);
  };
  const std::vector<FramePass>& steps = FrameSteps();
  for (size_t index = 0; index < steps.size(); ++index) {
    const PassDeclaration& pass = FramePassDeclaration(steps[index]);
    if (frame.Has(pass.effect)) pass.step(step);
    if (pass.pass == FramePass::kGBuffer) {
      // Only the effects the visible pixels need (docs/design.md §9). G-buffer word 3 has room for one
      // light's term: the first shadow-casting light's.
      Stopwatch planning;
      frame.plan = PlanFrame(scene, config, frame.gbuffer.gbuffer, frame.gbuffer.edgeCoverage, frame.view);
      stats.planMs = planning.Lap();
      frame.shadows = frame.plan.shadows.run && (from > FramePass::kShadowMap || to >= FramePass::kShadowMap);
      frame.reflections = frame.plan.reflections.run;
      frame.sky = frame.plan.sky.run;
      frame.bounce = frame.plan.bounce.run;
      frame.antialias = frame.plan.antialias.run;
    }
    if (observer) observer(steps[index], frame);
    release(index);
  }
  stats.totalMs = total.Lap();
}

std::vector<StageStats> StageRows(const FrameStats& stats) {
  std::vector<StageStats> rows;
  for (const PassDeclaration& pass : FramePasses()) {
    for (const StageRowDeclaration& declared : pass.stats) {
      std::optional<StageStats> row = declared.row(stats);
      if (!row) continue;
      row->name = declared.name;
      rows.push_back(std::move(*row));
    }
  }
  rows.push_back({"frame total", stats.totalMs, double(stats.pixels), "pixels"});
  return rows;
}

std::vector<uint8_t> AlbedoImage(const GBuffer& gbuffer) {
  const int width = gbuffer.width(), height = gbuffer.height();
  std::vector<uint8_t> rgb(size_t(width) * size_t(height) * 3);
  for (int y = 0; y < height; ++y) {
    const uint32_t* w0 = gbuffer.word[GBufferWord::kAlbedoMetallic].ConstRow(y);
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) rgb[(size_t(y) * width + x) * 3 + c] = uint8_t(w0[x] >> (8 * c));
  }
  return rgb;
}

}  // namespace ssgi
