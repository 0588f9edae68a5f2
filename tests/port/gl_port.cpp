// ssgi_gl_port: the passes of docs/pipeline.md (the G-buffer and the shadow map on GL's own
// rasterizer, the blocker search, the shadow filter, direct light, sky light, diffuse bounce, Hi-Z,
// colour pyramid, SSR trace, cone trace, composite, the anti-aliasing's coverage words, edge or
// MLAA, and its blend) as GLSL 4.50 shaders (tests/port/*.comp, *.vert, *.frag, written from the
// spec), run by OpenGL 4.5 core on an EGL surfaceless display
// (Mesa llvmpipe) on an ssgi dump's scene, writing its buffers under the dump's layer names so the
// two files compare layer by layer (tests/port/README.md).
//
//   ssgi_gl_port --scene SCENE IN.exr -o OUT.exr [--oracle-inputs] [--raster oracle|visibility|conventional]
//
// SCENE is the scene the dump was rendered from: its camera, and the pass parameters of its render
// block. The image size is the dump's. The rasterized buffers (G-buffer words 0-2, the shadow map)
// are the dump's unless --raster says GL's rasterizer makes them. Each pass reads the port's own
// earlier buffers, or with --oracle-inputs the oracle's from the dump where it holds them, so each
// pass is checked alone.
// Exit codes: 0 written, 1 bad input, 2 usage, 3 a GL error, 77 no EGL display or OpenGL 4.5
// context here (the test then skips).
#include <GL/glcorearb.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/egl_context.h"
#include "core/brdf.h"
#include "core/camera.h"
#include "core/color.h"
#include "core/environment_lighting.h"
#include "core/error.h"
#include "core/gbuffer.h"
#include "core/image_io.h"
#include "core/lighting.h"
#include "core/parallel.h"
#include "core/pyramid.h"
#include "core/scene.h"
#include "passes/bounce.h"
#include "passes/frame/config.h"
#include "passes/frame/dump.h"
#include "passes/mlaa.h"
#include "passes/sky_light.h"
#include "tests/port/gl_objects.h"
#include "tests/port/gl_raster.h"
#include "tests/port/gl_shadows.h"
#include "tests/port/gl_sky_volume.h"

namespace ssgi::port {
namespace {

constexpr int kExitNoGl = 77;
constexpr int kMaxLevels = 16;   // the shaders' uniform arrays of pyramid levels
constexpr GLuint kSrgbDecodeBinding = 15;  // common.glsl's sRGB table
constexpr GLuint kEnvironmentBinding = 14;  // common.glsl's environment levels

// What every pass reads of the frame: the image size, the camera and the normal encoding.
struct FrameConstants {
  int width = 0, height = 0;
  ViewProjection view;
  NormalEncoding normalEncoding = NormalEncoding::kOct24;
  std::vector<PyramidSize> levels;  // PyramidLevelSizes(width, height)
};

// The shadowed light's index in PrepareLights order (§Direct light): the first light that casts
// shadows, directional lights before spots; -1 when none does.
int ShadowedLight(const Scene& scene) {
  int index = 0;
  for (const DirectionalLight& light : scene.directionalLights) {
    if (light.castShadows) return index;
    ++index;
  }
  for (const SpotLight& light : scene.spotLights) {
    if (light.castShadows) return index;
    ++index;
  }
  return -1;
}

void SetFrameConstants(const Program& program, const FrameConstants& frame) {
  program.Set("imageSize", frame.width, frame.height);
  program.Set("tanHalf", frame.view.halfX, frame.view.halfY);
  program.Set("normalEncoding", frame.normalEncoding == NormalEncoding::kXyz8 ? 0 : 1);
}

// One buffer holding every level of a pyramid one after the other, for the passes that read every
// level; offsets in floats, per level.
struct Levels {
  Buffer all;
  std::vector<int> offsets;
  std::vector<int> sizes;  // x, y per level
};

Levels Concatenate(const std::vector<Buffer>& levels, const std::vector<PyramidSize>& sizes) {
  size_t total = 0;
  std::vector<int> offsets, xy;
  for (size_t k = 0; k < levels.size(); ++k) {
    offsets.push_back(int(total));
    total += levels[k].words();
    xy.push_back(int(sizes[k].width));
    xy.push_back(int(sizes[k].height));
  }
  Levels result{Buffer(total), offsets, xy};
  for (size_t k = 0; k < levels.size(); ++k)
    glCopyNamedBufferSubData(levels[k].id(), result.all.id(), 0, GLintptr(offsets[k]) * 4,
                             GLsizeiptr(levels[k].words() * 4));
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  return result;
}

// The dump's layer `name` of part `part`, or null; throws InputError naming `file` when it is of the
// other type than `isUint` says or not width x height.
const ExrLayer* FindLayer(const ExrFile& dump, const std::string& part, const std::string& name, bool isUint,
                          size_t width, size_t height, const std::filesystem::path& file) {
  const ExrLayer* layer = dump.Find(part, name);
  if (layer == nullptr) return nullptr;
  if (layer->isUint != isUint)
    throw InputError(file, "layer " + name + " is " + (layer->isUint ? "uint32" : "float") + ", must be " +
                               (isUint ? "uint32" : "float"));
  if (size_t(layer->width) != width || size_t(layer->height) != height)
    throw InputError(file, "layer " + name + " of part " + part + " is " + std::to_string(layer->width) + "x" +
                               std::to_string(layer->height) + ", must be " + std::to_string(width) + "x" +
                               std::to_string(height));
  return layer;
}

// The float channels `names` of part `part` (width x height), one plane after the other; nothing when
// the part lacks one.
std::optional<Buffer> UploadPlanes(const ExrFile& dump, const std::string& part, const std::vector<std::string>& names,
                                   size_t width, size_t height, const std::filesystem::path& file) {
  std::vector<uint32_t> planes;
  for (const std::string& name : names) {
    const ExrLayer* layer = FindLayer(dump, part, name, false, width, height, file);
    if (layer == nullptr) return std::nullopt;
    planes.insert(planes.end(), layer->samples.begin(), layer->samples.end());
  }
  return Buffer(planes.size(), planes.data());
}

// The uint32 layer `name` of part `part` (width x height); nothing when the part lacks it.
std::optional<Buffer> UploadWords(const ExrFile& dump, const std::string& part, const std::string& name, size_t width,
                                  size_t height, const std::filesystem::path& file) {
  const ExrLayer* layer = FindLayer(dump, part, name, true, width, height, file);
  if (layer == nullptr) return std::nullopt;
  return Buffer(layer->samples.size(), layer->samples.data());
}

// The dump's parts `prefix`0, `prefix`1, ... of the sizes `sizes`, channels `names`, as one buffer
// laid out as Concatenate lays out the port's; nothing when a level is missing.
std::optional<Levels> UploadLevels(const ExrFile& dump, const std::string& prefix, const std::vector<std::string>& names,
                                   const std::vector<PyramidSize>& sizes, const std::filesystem::path& file) {
  std::vector<Buffer> levels;
  for (size_t k = 0; k < sizes.size(); ++k) {
    std::optional<Buffer> level =
        UploadPlanes(dump, prefix + std::to_string(k), names, sizes[k].width, sizes[k].height, file);
    if (!level) return std::nullopt;
    levels.push_back(std::move(*level));
  }
  return Concatenate(levels, sizes);
}

// The oracle's buffer where the dump gave one (--oracle-inputs), else the port's own.
template <class T>
const T& Pick(const std::optional<T>& oracle, const T& own) {
  return oracle ? *oracle : own;
}

void SetLevels(const Program& program, const Levels& levels) {
  program.Set("levelCount", int(levels.offsets.size()));
  program.SetArray2("levelSizes", levels.sizes);
  program.SetArray("levelOffsets", levels.offsets);
}

size_t Pixels(const PyramidSize& size) { return size.width * size.height; }

// §Direct light, three planes. `visibility` is the shadow filter's output for the shadowed light,
// or null when the frame ran no shadows.
Buffer RunDirectLight(const FrameConstants& frame, const Scene& scene, const glm::vec3& background,
                      const std::vector<Buffer>& words, const Buffer* visibility) {
  const Program program("direct_light.comp");
  SetFrameConstants(program, frame);
  // Four vec4 per light, as direct_light.comp's Light.
  std::vector<float> packed;
  for (const PreparedLight& light : PrepareLights(scene, frame.view.view)) {
    const float fields[16] = {light.position.x,  light.position.y,  light.position.z,  light.isSpot ? 1.0f : 0.0f,
                              light.direction.x, light.direction.y, light.direction.z, light.radius,
                              light.power.x,     light.power.y,     light.power.z,     light.tanAngularRadius,
                              light.cosOuter,    light.coneScale,   0.0f,              0.0f};
    packed.insert(packed.end(), fields, fields + 16);
  }
  const Buffer lights(packed.size(), packed.data());
  program.Set("lightCount", int(packed.size() / 16));
  program.Set("shadowedLight", visibility != nullptr ? ShadowedLight(scene) : -1);
  program.Set("background", background.x, background.y, background.z);
  Buffer direct(3 * size_t(frame.width) * size_t(frame.height));
  for (GLuint w = 0; w < 3; ++w) words[w].Bind(w);
  if (visibility != nullptr) visibility->Bind(3);
  direct.Bind(4);
  lights.Bind(5);
  program.Dispatch(frame.width, frame.height);
  return direct;
}

// common.glsl's viewToWorld: the inverse view matrix's four columns.
void SetViewToWorld(const Program& program, const FrameConstants& frame) {
  const glm::mat4 toWorld = glm::inverse(frame.view.view);
  std::vector<float> columns;
  for (int c = 0; c < 4; ++c) columns.insert(columns.end(), {toWorld[c].x, toWorld[c].y, toWorld[c].z});
  program.SetArray3("viewToWorld", columns);
}

// The environment as the passes read it (§Environment lighting): core's tables, like the DFG table
// an input the spec defines and core builds. A constant environment has none: its radiance is a
// uniform. The levels are bound to kEnvironmentBinding, packed level by level, plane by plane.
struct EnvironmentTables {
  explicit EnvironmentTables(const Environment& environment)
      : lighting(PrepareEnvironmentLighting(environment)), levels(Pack(lighting, sizes, offsets)) {
    levels.Bind(kEnvironmentBinding);
  }
  // The uniforms of sky_light.comp and composite.comp that say which environment they read.
  void SetOn(const Program& program) const {
    program.Set("constantEnvironment", lighting.constant ? 1 : 0);
    if (lighting.constant) return;
    program.SetArray("levelSize", sizes);
    program.SetArray("levelOffset", offsets);
    std::vector<float> sh;
    for (const glm::vec3& k : lighting.irradianceSh) sh.insert(sh.end(), {k.x, k.y, k.z});
    program.SetArray3("irradianceSh", sh);
  }

  EnvironmentLighting lighting;
  std::vector<int> sizes, offsets;
  Buffer levels;

 private:
  static Buffer Pack(const EnvironmentLighting& lighting, std::vector<int>& sizes, std::vector<int>& offsets) {
    std::vector<float> texels;
    for (const OctahedralLevel& level : lighting.levels) {
      sizes.push_back(level.size);
      offsets.push_back(int(texels.size()));
      const size_t side = size_t(level.size) + 2;
      for (int c = 0; c < 3 && !lighting.constant; ++c)
        for (size_t j = 0; j < side; ++j) {
          const float* row = level.texels.c[c].ConstRow(j);
          texels.insert(texels.end(), row, row + side);
        }
    }
    return Buffer(texels.size(), texels.data());
  }
};

struct SkyLightOutput {
  Buffer diffuse, visibility, lit;
  std::optional<Buffer> reflected;  // with the interreflection volume
};

// §Sky light: `volume` the oracle's sky visibility volume (its grid is the scene's).
SkyLightOutput RunSkyLight(const FrameConstants& frame, const SkyVisibilityVolume& grid, const Buffer& volume,
                           const Buffer* interreflection, const EnvironmentTables& environment,
                           const std::vector<Buffer>& words, const Buffer& direct) {
  const Program program("sky_light.comp");
  SetFrameConstants(program, frame);
  SetViewToWorld(program, frame);
  program.Set("cells", grid.cellsX, grid.cellsY, grid.cellsZ);
  program.Set("origin", grid.origin.x, grid.origin.y, grid.origin.z);
  program.Set("cellSize", grid.cellSize);
  program.Set("inverseCellSize", grid.inverseCellSize);
  environment.SetOn(program);
  const glm::vec3 radiance = environment.lighting.constantRadiance;
  program.Set("environmentRadiance", radiance.x, radiance.y, radiance.z);
  const size_t pixels = size_t(frame.width) * size_t(frame.height);
  SkyLightOutput out{Buffer(3 * pixels), Buffer(pixels), Buffer(3 * pixels), {}};
  if (interreflection) out.reflected.emplace(3 * pixels);
  for (GLuint w = 0; w < 3; ++w) words[w].Bind(w);
  direct.Bind(3);
  volume.Bind(4);
  out.diffuse.Bind(5);
  out.visibility.Bind(6);
  out.lit.Bind(7);
  program.Set("hasInterreflection", interreflection ? 1 : 0);
  // Bound either way: a shader's storage buffer must be backed even where it is not read.
  (interreflection ? *interreflection : volume).Bind(8);
  (interreflection ? *out.reflected : out.lit).Bind(9);
  program.Dispatch(frame.width, frame.height);
  return out;
}

// §Diffuse bounce and ambient occlusion: the half-resolution steps' buffers (as the dump's part
// bounce.half names them) and the full-resolution outputs. Several channels: planes one after the
// other.
struct BounceBuffers {
  Buffer depth, normal, normalCode, lit;
  Buffer marchVisibility, march, rowsVisibility, rows, filteredVisibility, filtered;
  Buffer visibility, bounce;
};

// The dump's part holding the bounce's half-resolution steps, and its layers in BounceBuffers' order.
const char kBounceHalfPart[] = "bounce.half";

// The oracle's bounce buffers each step reads, where the dump holds them (--oracle-inputs): prepare
// reads only the G-buffer and `lit`, so the first is the half-resolution inputs.
struct OracleBounce {
  std::optional<Buffer> depth, normal, normalCode, lit;
  std::optional<Buffer> marchVisibility, march, rowsVisibility, rows, filteredVisibility, filtered;
  std::optional<Buffer> visibility, bounce;
};

OracleBounce UploadOracleBounce(const ExrFile& dump, const FrameConstants& frame, const std::filesystem::path& file) {
  const size_t halfWidth = size_t(frame.width + 1) / 2, halfHeight = size_t(frame.height + 1) / 2;
  const auto half = [&](const std::vector<std::string>& names) {
    return UploadPlanes(dump, kBounceHalfPart, names, halfWidth, halfHeight, file);
  };
  OracleBounce oracle;
  oracle.depth = half({"depth"});
  oracle.normal = half({"normal.X", "normal.Y", "normal.Z"});
  oracle.normalCode = UploadWords(dump, kBounceHalfPart, "normalCode", halfWidth, halfHeight, file);
  oracle.lit = half({"lit.R", "lit.G", "lit.B"});
  oracle.marchVisibility = half({"march.visibility"});
  oracle.march = half({"march.R", "march.G", "march.B"});
  oracle.rowsVisibility = half({"rows.visibility"});
  oracle.rows = half({"rows.R", "rows.G", "rows.B"});
  oracle.filteredVisibility = half({"filtered.visibility"});
  oracle.filtered = half({"filtered.R", "filtered.G", "filtered.B"});
  const size_t width = size_t(frame.width), height = size_t(frame.height);
  oracle.visibility = UploadPlanes(dump, "frame", {"bounce.visibility"}, width, height, file);
  oracle.bounce = UploadPlanes(dump, "frame", {"bounce.R", "bounce.G", "bounce.B"}, width, height, file);
  return oracle;
}

// The direction table (§Diffuse bounce, set-up): for slice k and rotation phase r, angle = pi (k +
// (r + 0.5) / 16) / slices in double, its cos and sin rounded once; (x, y) pairs at [16 k + r].
std::vector<float> BounceDirections(int slices) {
  std::vector<float> xy;
  for (int k = 0; k < slices; ++k) {
    for (int r = 0; r < 16; ++r) {
      const double angle = 3.14159265358979323846 * (double(k) + (double(r) + 0.5) / 16.0) / double(slices);
      xy.push_back(float(std::cos(angle)));
      xy.push_back(float(std::sin(angle)));
    }
  }
  return xy;
}

// The bounce's five steps on `lit` (the sky light's, else the direct light). Each step reads the
// port's own earlier buffers, or the oracle's where `oracle` holds them.
BounceBuffers RunBounce(const FrameConstants& frame, const BounceParams& params, const std::vector<Buffer>& words,
                        const Buffer& lit, const OracleBounce& oracle) {
  enum Stage { kPrepare = 0, kMarch = 1, kFilterRows = 2, kFilterColumns = 3, kUpsample = 4 };
  const Program program("bounce.comp");
  SetFrameConstants(program, frame);
  const int halfWidth = (frame.width + 1) / 2, halfHeight = (frame.height + 1) / 2;
  program.Set("halfSize", halfWidth, halfHeight);
  program.Set("slices", params.slices);
  program.Set("steps", params.steps);
  program.Set("sectors", params.sectors);
  program.Set("radius", params.radius);
  program.Set("maxRadiusPixels", params.maxRadiusPixels);
  program.Set("thickness", params.thickness);
  program.Set("depthTolerance", params.depthTolerance);
  const std::vector<float> table = BounceDirections(params.slices);
  const Buffer directions(table.size(), table.data());
  const size_t half = size_t(halfWidth) * size_t(halfHeight), pixels = size_t(frame.width) * size_t(frame.height);
  BounceBuffers out{Buffer(half), Buffer(3 * half), Buffer(half), Buffer(3 * half), Buffer(half),   Buffer(3 * half),
                    Buffer(half), Buffer(3 * half), Buffer(half), Buffer(3 * half), Buffer(pixels), Buffer(3 * pixels)};
  words[1].Bind(0);
  words[2].Bind(1);
  lit.Bind(2);
  directions.Bind(11);
  const auto dispatch = [&](Stage stage) {
    program.Set("stage", int(stage));
    if (stage == kUpsample) {
      program.Dispatch(frame.width, frame.height);
    } else {
      program.Dispatch(halfWidth, halfHeight);
    }
  };
  // Prepare writes the half-resolution inputs (bindings 3-6); the later steps read them, the oracle's
  // where taken.
  out.depth.Bind(3);
  out.normal.Bind(4);
  out.normalCode.Bind(5);
  out.lit.Bind(6);
  dispatch(kPrepare);
  Pick(oracle.depth, out.depth).Bind(3);
  Pick(oracle.normal, out.normal).Bind(4);
  Pick(oracle.normalCode, out.normalCode).Bind(5);
  Pick(oracle.lit, out.lit).Bind(6);
  // The march and the steps after it write a visibility and a bounce (bindings 9, 10); the filter's
  // passes and the upsample read the step's before them (7, 8).
  const auto run = [&](Stage stage, const Buffer* sourceVisibility, const Buffer* sourceBounce,
                       const Buffer& visibility, const Buffer& bounce) {
    if (sourceVisibility != nullptr) {
      sourceVisibility->Bind(7);
      sourceBounce->Bind(8);
    }
    visibility.Bind(9);
    bounce.Bind(10);
    dispatch(stage);
  };
  run(kMarch, nullptr, nullptr, out.marchVisibility, out.march);
  run(kFilterRows, &Pick(oracle.marchVisibility, out.marchVisibility), &Pick(oracle.march, out.march),
      out.rowsVisibility, out.rows);
  run(kFilterColumns, &Pick(oracle.rowsVisibility, out.rowsVisibility), &Pick(oracle.rows, out.rows),
      out.filteredVisibility, out.filtered);
  run(kUpsample, &Pick(oracle.filteredVisibility, out.filteredVisibility), &Pick(oracle.filtered, out.filtered),
      out.visibility, out.bounce);
  return out;
}

// §Hi-Z pyramid: level 0 = 1 / word 2, then each level the max of its footprint.
std::vector<Buffer> RunHiZ(const FrameConstants& frame, const Buffer& word2) {
  const Program program("hiz.comp");
  std::vector<Buffer> levels;
  for (size_t k = 0; k < frame.levels.size(); ++k) {
    const PyramidSize destination = frame.levels[k], source = frame.levels[k == 0 ? 0 : k - 1];
    levels.emplace_back(Pixels(destination));
    (k == 0 ? word2 : levels[k - 1]).Bind(0);
    levels[k].Bind(1);
    program.Set("invertDepth", k == 0 ? 1 : 0);
    program.Set("sourceSize", int(source.width), int(source.height));
    program.Set("destinationSize", int(destination.width), int(destination.height));
    program.Dispatch(int(destination.width), int(destination.height));
  }
  return levels;
}

// §Colour pyramid: level 0 = the sanitised direct light; level k+1 = level k blurred horizontally,
// vertically, then area-averaged over each footprint. Three planes per level.
std::vector<Buffer> RunColorPyramid(const FrameConstants& frame, const Buffer& direct) {
  enum Stage { kSanitize = 0, kHorizontal = 1, kVertical = 2, kDownsample = 3 };
  const Program program("color_pyramid.comp");
  // Uludag's 7 taps, normalised in double, then rounded (kColorPyramidWeights).
  const double taps[7] = {0.001, 0.028, 0.233, 0.474, 0.233, 0.028, 0.001};
  std::vector<float> weights;
  for (double tap : taps) weights.push_back(float(tap / 0.998));
  program.SetArray("weights", weights);
  program.Set("level0Size", frame.width, frame.height);
  const auto run = [&](Stage stage, const Buffer& source, const Buffer& destination, PyramidSize sourceSize,
                       PyramidSize destinationSize) {
    source.Bind(0);
    destination.Bind(1);
    program.Set("stage", int(stage));
    program.Set("sourceSize", int(sourceSize.width), int(sourceSize.height));
    program.Set("destinationSize", int(destinationSize.width), int(destinationSize.height));
    program.Dispatch(int(destinationSize.width), int(destinationSize.height), 3);
  };
  std::vector<Buffer> levels;
  levels.emplace_back(3 * Pixels(frame.levels[0]));
  run(kSanitize, direct, levels[0], frame.levels[0], frame.levels[0]);
  for (size_t k = 0; k + 1 < frame.levels.size(); ++k) {
    const PyramidSize size = frame.levels[k];
    const Buffer horizontal(3 * Pixels(size)), vertical(3 * Pixels(size));
    run(kHorizontal, levels[k], horizontal, size, size);
    run(kVertical, horizontal, vertical, size, size);
    levels.emplace_back(3 * Pixels(frame.levels[k + 1]));
    program.Set("sourceLevel", int(k));
    run(kDownsample, vertical, levels[k + 1], size, frame.levels[k + 1]);
  }
  return levels;
}

struct TraceOutput {
  Buffer hitX, hitY, confidence, iterations;
};

TraceOutput RunSsrTrace(const FrameConstants& frame, const SsrTraceParams& params, const Buffer& word1,
                        const Buffer& word2, const Levels& hiz) {
  const Program program("ssr_trace.comp");
  SetFrameConstants(program, frame);
  SetLevels(program, hiz);
  program.Set("nearPlane", frame.view.nearPlane);
  program.Set("maxIterations", params.maxIterations);
  program.Set("startLevel", params.startLevel);
  program.Set("roughnessCutoff", params.roughnessCutoff);
  program.Set("thickness", params.thickness);
  program.Set("edgeFade", params.edgeFade);
  program.Set("towardCameraFade", params.towardCameraFade);
  program.Set("quadRoughness", params.quadRoughness);
  program.Set("blockRoughness", params.blockRoughness);
  const size_t pixels = size_t(frame.width) * size_t(frame.height);
  TraceOutput out{Buffer(pixels), Buffer(pixels), Buffer(pixels), Buffer(pixels)};
  word1.Bind(0);
  word2.Bind(1);
  hiz.all.Bind(2);
  out.hitX.Bind(3);
  out.hitY.Bind(4);
  out.confidence.Bind(5);
  out.iterations.Bind(6);
  program.Dispatch(frame.width, frame.height);
  return out;
}

// tan(theta) per roughness code (§SSR: cone trace): r = code / 255, alpha = r^2, Phong exponent
// n = min(2 / alpha^2 - 2, 1e6), theta = acos(0.244^(1 / (n + 1))); in double, rounded once.
std::vector<float> ConeTanTable() {
  std::vector<float> table;
  for (int code = 0; code < 256; ++code) {
    const double alpha = (code / 255.0) * (code / 255.0);
    const double exponent = std::min(2.0 / (alpha * alpha) - 2.0, 1e6);
    table.push_back(float(std::tan(std::acos(std::pow(0.244, 1.0 / (exponent + 1.0))))));
  }
  return table;
}

// The trace's outputs the cone trace and the composite read.
struct TraceHits {
  const Buffer& hitX;
  const Buffer& hitY;
  const Buffer& confidence;
};

Buffer RunSsrCone(const FrameConstants& frame, const SsrConeParams& params, const Buffer& word1,
                  const TraceHits& trace, const Levels& pyramid) {
  const Program program("ssr_cone.comp");
  SetFrameConstants(program, frame);
  SetLevels(program, pyramid);
  program.SetArray("coneTan", ConeTanTable());
  program.Set("maxSamples", params.maxSamples);
  Buffer reflected(3 * size_t(frame.width) * size_t(frame.height));
  word1.Bind(0);
  trace.hitX.Bind(1);
  trace.hitY.Bind(2);
  trace.confidence.Bind(3);
  pyramid.all.Bind(4);
  reflected.Bind(5);
  program.Dispatch(frame.width, frame.height);
  return reflected;
}

struct CompositeOutput {
  Buffer indirect, result;
};

// What the composite reads of the diffuse bounce: its light and visibility, and the sky light's
// diffuse term that the visibility darkens (null without the sky light).
struct CompositeBounce {
  const Buffer& bounce;
  const Buffer& visibility;
  const Buffer* skyDiffuse;
};

// `skyVisibility` the sky light's, null without it; `environment` the frame's; `bounce` null
// without the diffuse bounce.
CompositeOutput RunComposite(const FrameConstants& frame, float roughnessCutoff, const std::vector<Buffer>& words,
                             const Buffer& confidence, const Buffer& reflected, const Buffer& direct,
                             const Buffer* skyVisibility, const Buffer* skyReflected,
                             const EnvironmentTables& environment, const CompositeBounce* bounce) {
  const Program program("composite.comp");
  SetFrameConstants(program, frame);
  program.Set("roughnessCutoff", roughnessCutoff);
  program.Set("reflections", 1);
  program.Set("sky", skyVisibility != nullptr ? 1 : 0);
  environment.SetOn(program);
  const glm::vec3 radiance = environment.lighting.constantRadiance;
  program.Set("skyRadiance", radiance.x, radiance.y, radiance.z);
  SetViewToWorld(program, frame);
  // The table the spec defines and core builds (core/brdf.h).
  static_assert(sizeof(glm::vec2) == 2 * sizeof(float));
  const Buffer dfg(size_t(2 * kDfgSize * kDfgSize), &ShippedDfgTable().ab[0].x);
  const size_t planes = 3 * size_t(frame.width) * size_t(frame.height);
  CompositeOutput out{Buffer(planes), Buffer(planes)};
  for (GLuint w = 0; w < 3; ++w) words[w].Bind(w);
  confidence.Bind(3);
  reflected.Bind(4);
  direct.Bind(5);
  out.indirect.Bind(6);
  out.result.Bind(7);
  dfg.Bind(8);
  if (skyVisibility != nullptr) skyVisibility->Bind(9);
  program.Set("hasSkyReflected", skyReflected != nullptr ? 1 : 0);
  if (skyReflected != nullptr) skyReflected->Bind(13);
  program.Set("bounceRan", bounce != nullptr ? 1 : 0);
  if (bounce != nullptr) {
    bounce->bounce.Bind(10);
    bounce->visibility.Bind(11);
    if (bounce->skyDiffuse != nullptr) bounce->skyDiffuse->Bind(12);
  }
  program.Dispatch(frame.width, frame.height);
  return out;
}

// §Edge coverage and anti-aliasing, "Blend": `image` blended by the coverage words.
Buffer RunAntialias(const FrameConstants& frame, const Buffer& coverage, const Buffer& image) {
  const Program program("antialias.comp");
  SetFrameConstants(program, frame);
  Buffer blended(3 * size_t(frame.width) * size_t(frame.height));
  coverage.Bind(0);
  image.Bind(1);
  blended.Bind(2);
  program.Dispatch(frame.width, frame.height);
  return blended;
}

// §Edge coverage and anti-aliasing: the coverage words of the geometric edges the visibility
// buffer's `triangles` and word 2 show, from the scene's vertices.
Buffer RunEdgeCoverage(const FrameConstants& frame, const SceneBuffers& scene, const Buffer& triangles,
                       const Buffer& word2) {
  const Program program("edge_coverage.comp", {"surface.glsl"});
  SetFrameConstants(program, frame);
  program.SetMatrix("viewProjection", &frame.view.viewProjection[0][0]);
  Buffer coverage(size_t(frame.width) * size_t(frame.height));
  scene.Bind();
  triangles.Bind(0);
  word2.Bind(1);
  coverage.Bind(2);
  program.Dispatch(frame.width, frame.height);
  return coverage;
}

// §Morphological anti-aliasing: each step's buffer, as the dump names them (mlaa.luma, .edges,
// .weights, .coverage).
struct MlaaBuffers {
  Buffer luma, edges, weights, coverage;
};

// The oracle's MLAA buffers each step reads, where the dump holds them (--oracle-inputs).
struct OracleMlaa {
  std::optional<Buffer> luma, edges, weights;
};

// The four steps on `image` (the composite's result) seen through the tonemap's exposure. Each step
// reads the port's own earlier buffer, or the oracle's where `oracle` holds it.
MlaaBuffers RunMlaa(const FrameConstants& frame, float exposureEv, const Buffer& image, const OracleMlaa& oracle) {
  const Program program("mlaa.comp");
  SetFrameConstants(program, frame);
  program.Set("exposureScale", std::exp2(exposureEv));
  program.Set("threshold", MlaaParams{}.threshold);
  const size_t pixels = size_t(frame.width) * size_t(frame.height);
  MlaaBuffers out{Buffer(pixels), Buffer(pixels), Buffer(pixels), Buffer(pixels)};
  // Stage k (luma, edges, weights, coverage) writes binding k + 1; the next stage reads it there.
  const Buffer* own[] = {&out.luma, &out.edges, &out.weights, &out.coverage};
  const std::optional<Buffer>* theirs[] = {&oracle.luma, &oracle.edges, &oracle.weights};
  image.Bind(0);
  for (GLuint k = 0; k < 4; ++k) own[k]->Bind(k + 1);
  for (int stage = 0; stage < 4; ++stage) {
    program.Set("stage", stage);
    program.Dispatch(frame.width, frame.height);
    if (stage < 3) Pick(*theirs[stage], *own[stage]).Bind(GLuint(stage + 1));
  }
  return out;
}

// Plane `plane` of a buffer of planes of width x height words each, as the float layer `name` of part
// `part`.
ExrLayer PlaneLayer(const std::string& part, const std::string& name, const std::vector<uint32_t>& words, size_t plane,
                    int width, int height) {
  const size_t pixels = size_t(width) * size_t(height);
  return ExrLayer{part, name, width, height, false,
                  std::vector<uint32_t>(words.begin() + std::ptrdiff_t(plane * pixels),
                                        words.begin() + std::ptrdiff_t((plane + 1) * pixels))};
}

// The bounce's half-resolution steps as the dump's part bounce.half (halfWidth x halfHeight).
void AddBounceHalfLayers(const BounceBuffers& bounce, int halfWidth, int halfHeight, ExrFile& out) {
  const auto add = [&](const Buffer& buffer, const std::vector<std::string>& names, bool isUint = false) {
    const std::vector<uint32_t> planes = buffer.Download();
    for (size_t c = 0; c < names.size(); ++c) {
      ExrLayer layer = PlaneLayer(kBounceHalfPart, names[c], planes, c, halfWidth, halfHeight);
      layer.isUint = isUint;
      out.layers.push_back(std::move(layer));
    }
  };
  add(bounce.depth, {"depth"});
  add(bounce.normal, {"normal.X", "normal.Y", "normal.Z"});
  add(bounce.normalCode, {"normalCode"}, true);
  add(bounce.lit, {"lit.R", "lit.G", "lit.B"});
  add(bounce.marchVisibility, {"march.visibility"});
  add(bounce.march, {"march.R", "march.G", "march.B"});
  add(bounce.rowsVisibility, {"rows.visibility"});
  add(bounce.rows, {"rows.R", "rows.G", "rows.B"});
  add(bounce.filteredVisibility, {"filtered.visibility"});
  add(bounce.filtered, {"filtered.R", "filtered.G", "filtered.B"});
}

// Where the rasterized buffers (G-buffer words 0-2 and the shadow map) come from: the oracle's dump,
// so every pass after them can be held to the oracle's bits, or GL's rasterizer, with the G-buffer
// in one of its two forms (tests/port/gl_raster.h).
enum class RasterSource { kOracle, kVisibility, kConventional };

// The layers `sink` holds, appended to `out`.
void AppendDumpLayers(const DumpSink& sink, ExrFile& out) {
  for (const ExrPart& part : sink.Parts()) {
    for (const ExrChannel& channel : part.channels) {
      ExrLayer layer{part.name, channel.name, part.width, part.height, channel.isUint, {}};
      const auto* samples = static_cast<const uint32_t*>(channel.data);
      for (size_t y = 0; y < size_t(part.height); ++y)
        layer.samples.insert(layer.samples.end(), samples + y * channel.rowStride,
                             samples + y * channel.rowStride + size_t(part.width));
      out.layers.push_back(std::move(layer));
    }
  }
}

int Run(const std::filesystem::path& scenePath, const std::filesystem::path& input, const std::filesystem::path& output,
        bool oracleInputs, RasterSource raster, int subpixelBits) {
  const ExrFile dump = ReadExrFile(input);
  // The image part: "frame" in ssgi's dumps.
  const std::string main = "frame";
  const ExrLayer* word0 = dump.Find(main, "gbuffer.word0");
  if (word0 == nullptr) throw InputError(input, "has no layer gbuffer.word0 in a part 'frame'");
  // The scene and settings the dump was rendered with, as `ssgi passes` takes them.
  const DumpScene scene = LoadDumpScene(dump, input, scenePath);
  const FrameConfig& config = scene.config;
  FrameConstants frame;
  frame.width = word0->width;
  frame.height = word0->height;
  frame.view = MakePerspective(scene.scene.camera, frame.width, frame.height);
  frame.normalEncoding = config.normalEncoding;
  frame.levels = PyramidLevelSizes(size_t(frame.width), size_t(frame.height));
  if (frame.levels.size() > size_t(kMaxLevels)) throw InputError(input, "is larger than the port's 16 levels allow");
  const size_t pixels = size_t(frame.width) * size_t(frame.height);

  std::string error;
  // llvmpipe rasterizes and runs its compute dispatches on LP_NUM_THREADS threads.
  const auto context = LlvmpipeContext::Open(HardwareThreads(), error);
  if (!context) {
    std::fprintf(stderr, "ssgi_gl_port: skipped: %s\n", error.c_str());
    return kExitNoGl;
  }
  // The rasterizer's sub-pixel precision, which the coverage rule assumes is at least 8 bits.
  GLint glSubpixelBits = 0;
  glGetIntegerv(GL_SUBPIXEL_BITS, &glSubpixelBits);
  std::printf("ssgi_gl_port: %s, GL_SUBPIXEL_BITS %d\n", context->renderer().c_str(), int(glSubpixelBits));

  // The G-buffer's albedo codes and sRGB textures decode through core's sRGB table (core/color.h).
  const Buffer srgbDecode(256, SrgbDecodeTableForKernels());
  srgbDecode.Bind(kSrgbDecodeBinding);
  std::optional<SceneBuffers> sceneBuffers;
  std::optional<PortGBuffer> gbuffer;
  if (raster != RasterSource::kOracle) {
    sceneBuffers.emplace(scene.scene);
    gbuffer = RunGBufferPass(
        *sceneBuffers, frame.view, frame.normalEncoding, config.specularAaKappa,
        raster == RasterSource::kVisibility ? GBufferForm::kVisibility : GBufferForm::kConventional, subpixelBits);
  }
  std::vector<Buffer> words;
  const size_t width = size_t(frame.width), height = size_t(frame.height);
  for (int w = 0; w < 3; ++w) {
    if (gbuffer) {
      words.push_back(std::move(gbuffer->words[size_t(w)]));
      continue;
    }
    const std::string name = "gbuffer.word" + std::to_string(w);
    const ExrLayer* layer = FindLayer(dump, main, name, true, width, height, input);
    if (layer == nullptr) throw InputError(input, "has no layer " + name);
    words.emplace_back(pixels, layer->samples.data());
  }
  // The shadow passes, where the frame ran them (the dump has the filter's output): the map (the
  // oracle's with the oracle's G-buffer, else GL's), word 3 and the visibility, each on the port's
  // own earlier buffers or, with --oracle-inputs, on the oracle's word 3.
  const bool shadows = dump.Find(main, "shadow.visibility") != nullptr;
  std::optional<ShadowMapResult> shadowMap;
  std::optional<Buffer> word3, visibility, oracleShadowMap, oracleWord3, oracleVisibility;
  if (shadows) {
    if (!sceneBuffers) sceneBuffers.emplace(scene.scene);
    const ShadowInputs in{scene.scene, *sceneBuffers, frame.view, frame.normalEncoding, words[1], words[2]};
    const size_t resolution = size_t(config.shadowMap.resolution);
    shadowMap = RunPortShadowMap(in, config.shadowMap, raster != RasterSource::kOracle);
    if (raster == RasterSource::kOracle) {
      oracleShadowMap = UploadPlanes(dump, "shadowmap", {"depthKey"}, resolution, resolution, input);
      if (!oracleShadowMap) throw InputError(input, "has no layer depthKey in a part 'shadowmap'");
    }
    if (oracleInputs) {
      oracleWord3 = UploadWords(dump, main, "gbuffer.word3", width, height, input);
      oracleVisibility = UploadPlanes(dump, main, {"shadow.visibility"}, width, height, input);
    }
    word3 = RunPortBlockerSearch(in, config.shadowMap, shadowMap->lightView,
                                 oracleShadowMap ? *oracleShadowMap : shadowMap->depthKey);
    visibility = RunPortShadowFilter(in, config.shadowFilter, oracleWord3 ? *oracleWord3 : *word3);
  }

  // The oracle's buffers that passes read, where the dump holds them (--oracle-inputs).
  std::optional<Buffer> oracleDirect, oracleLit, oracleSkyVisibility, oracleSkyDiffuse, oracleSkyReflected, oracleHitX,
      oracleHitY, oracleConfidence, oracleReflected;
  OracleBounce oracleBounce;
  std::optional<Levels> oracleHiZ, oraclePyramid;
  std::optional<Buffer> oracleResult, oracleCoverage;
  OracleMlaa oracleMlaa;
  if (oracleInputs) {
    oracleDirect = UploadPlanes(dump, main, {"direct.R", "direct.G", "direct.B"}, width, height, input);
    oracleLit = UploadPlanes(dump, main, {"lit.R", "lit.G", "lit.B"}, width, height, input);
    oracleSkyVisibility = UploadPlanes(dump, main, {"sky.visibility"}, width, height, input);
    oracleSkyDiffuse =
        UploadPlanes(dump, main, {"sky.diffuse.R", "sky.diffuse.G", "sky.diffuse.B"}, width, height, input);
    oracleSkyReflected =
        UploadPlanes(dump, main, {"sky.reflected.R", "sky.reflected.G", "sky.reflected.B"}, width, height, input);
    oracleBounce = UploadOracleBounce(dump, frame, input);
    oracleHitX = UploadPlanes(dump, main, {"ssr.hitX"}, width, height, input);
    oracleHitY = UploadPlanes(dump, main, {"ssr.hitY"}, width, height, input);
    oracleConfidence = UploadPlanes(dump, main, {"ssr.confidence"}, width, height, input);
    oracleReflected =
        UploadPlanes(dump, main, {"ssr.reflected.R", "ssr.reflected.G", "ssr.reflected.B"}, width, height, input);
    oracleHiZ = UploadLevels(dump, "hiz.", {"Y"}, frame.levels, input);
    oraclePyramid = UploadLevels(dump, "pyramid.", {"R", "G", "B"}, frame.levels, input);
    oracleResult = UploadPlanes(dump, main, {"result.R", "result.G", "result.B"}, width, height, input);
    oracleMlaa.luma = UploadPlanes(dump, main, {"mlaa.luma"}, width, height, input);
    oracleMlaa.edges = UploadWords(dump, main, "mlaa.edges", width, height, input);
    oracleMlaa.weights = UploadWords(dump, main, "mlaa.weights", width, height, input);
    oracleCoverage = UploadWords(dump, main, "aa.coverage", width, height, input);
    if (!oracleCoverage) oracleCoverage = UploadWords(dump, main, "mlaa.coverage", width, height, input);
    std::string taken;
    const auto note = [&](bool found, const char* what) { taken += found ? std::string(" ") + what : ""; };
    note(oracleWord3.has_value(), "word3");
    note(oracleVisibility.has_value(), "shadow.visibility");
    note(oracleDirect.has_value(), "direct");
    note(oracleLit.has_value(), "lit");
    note(oracleBounce.depth && oracleBounce.normal && oracleBounce.normalCode && oracleBounce.lit,
         "bounce.half:inputs");
    note(oracleBounce.marchVisibility && oracleBounce.march, "bounce.half:march");
    note(oracleBounce.rowsVisibility && oracleBounce.rows, "bounce.half:rows");
    note(oracleBounce.filteredVisibility && oracleBounce.filtered, "bounce.half:filtered");
    note(oracleBounce.visibility && oracleBounce.bounce, "bounce");
    note(oracleHiZ.has_value(), "hiz");
    note(oraclePyramid.has_value(), "pyramid");
    note(oracleHitX && oracleHitY && oracleConfidence, "ssr.hit");
    note(oracleReflected.has_value(), "ssr.reflected");
    note(oracleResult.has_value(), "result");
    note(oracleMlaa.luma.has_value(), "mlaa.luma");
    note(oracleMlaa.edges.has_value(), "mlaa.edges");
    note(oracleMlaa.weights.has_value(), "mlaa.weights");
    note(oracleCoverage.has_value(), "coverage");
    std::printf("ssgi_gl_port: the oracle's inputs taken from the dump:%s\n", taken.empty() ? " none" : taken.c_str());
  }

  const Buffer* lightVisibility = oracleVisibility ? &*oracleVisibility : visibility ? &*visibility : nullptr;
  const Buffer direct = RunDirectLight(frame, scene.scene, config.environment.MeanRadiance(), words, lightVisibility);
  // The sky light, where the frame ran it (its volume in the dump): then the passes after it read `lit`.
  std::optional<SkyLightOutput> sky;
  std::optional<ExrLayer> skyVolume;  // the port's, where it built one
  std::vector<ExrLayer> interreflectionLayers;  // the oracle's, passed on
  const EnvironmentTables environment(config.environment);
  if (const ExrLayer* volume = dump.Find("skyvolume", "k")) {
    const SkyVisibilityVolume grid = SkyVisibilityGrid(scene.scene, config.skyVisibility);
    if (volume->width != grid.cellsX * 4 || volume->height != grid.cellsY * grid.cellsZ)
      throw InputError(input, "layer 'k' of part 'skyvolume' is not the scene's sky visibility grid");
    // Where the port rasterizes, its own volume (GL's maps); else the dump's, so that the later
    // layers stay the oracle's bits.
    const Buffer volumeBuffer = raster != RasterSource::kOracle
                                    ? RunPortSkyVolume(*sceneBuffers, grid)
                                    : Buffer(volume->samples.size(), volume->samples.data());
    if (raster != RasterSource::kOracle)
      skyVolume.emplace(ExrLayer{"skyvolume", "k", volume->width, volume->height, false, volumeBuffer.Download()});
    // The interreflection volume is made with rays through the scene (Embree): the port takes the
    // oracle's, as an engine bakes one offline, and passes it on in its dump.
    std::optional<Buffer> interreflection;
    std::vector<uint32_t> channels;
    for (const char* name : {"interreflection.R", "interreflection.G", "interreflection.B"}) {
      const ExrLayer* channel = dump.Find("skyvolume", name);
      if (channel == nullptr) break;
      if (channel->width != volume->width || channel->height != volume->height)
        throw InputError(input, std::string("layer '") + name + "' of part 'skyvolume' is not the volume's grid");
      channels.insert(channels.end(), channel->samples.begin(), channel->samples.end());
      interreflectionLayers.push_back(*channel);
    }
    if (interreflectionLayers.size() == 3) interreflection.emplace(channels.size(), channels.data());
    sky = RunSkyLight(frame, grid, volumeBuffer, interreflection ? &*interreflection : nullptr, environment, words,
                      Pick(oracleDirect, direct));
  }
  const Buffer& lit = sky ? Pick(oracleLit, sky->lit) : Pick(oracleDirect, direct);
  // The diffuse bounce, where the frame ran it (its layers in the dump), on `lit`.
  std::optional<BounceBuffers> bounce;
  if (dump.Find(main, "bounce.visibility") != nullptr)
    bounce = RunBounce(frame, config.diffuseBounce, words, lit, oracleBounce);
  const std::vector<Buffer> hizLevels = RunHiZ(frame, words[2]);
  const std::vector<Buffer> pyramidLevels = RunColorPyramid(frame, lit);
  const Levels hiz = Concatenate(hizLevels, frame.levels);
  const Levels pyramid = Concatenate(pyramidLevels, frame.levels);
  const TraceOutput trace = RunSsrTrace(frame, config.ssrTrace, words[1], words[2], Pick(oracleHiZ, hiz));
  const TraceHits hits{Pick(oracleHitX, trace.hitX), Pick(oracleHitY, trace.hitY),
                       Pick(oracleConfidence, trace.confidence)};
  const Buffer reflected = RunSsrCone(frame, config.ssrCone, words[1], hits, Pick(oraclePyramid, pyramid));
  std::optional<CompositeBounce> compositeBounce;
  if (bounce)
    compositeBounce.emplace(CompositeBounce{Pick(oracleBounce.bounce, bounce->bounce),
                                            Pick(oracleBounce.visibility, bounce->visibility),
                                            sky ? &Pick(oracleSkyDiffuse, sky->diffuse) : nullptr});
  const CompositeOutput composite =
      RunComposite(frame, config.ssrTrace.roughnessCutoff, words, hits.confidence, Pick(oracleReflected, reflected),
                   lit, sky ? &Pick(oracleSkyVisibility, sky->visibility) : nullptr,
                   sky && sky->reflected ? &Pick(oracleSkyReflected, *sky->reflected) : nullptr, environment,
                   bounce ? &compositeBounce.value() : nullptr);
  // The anti-aliasing's coverage words, where the frame made them: those of the geometric edges (--aa
  // edge, from the visibility buffer: the port's where it rasterized, else the dump's) or of the
  // image's morphological edges (--aa mlaa); then the blend by them over the port's result, where the
  // frame ran it (some word is not 0).
  const Buffer& result = Pick(oracleResult, composite.result);
  std::optional<Buffer> edgeCoverage;
  std::optional<MlaaBuffers> mlaa;
  if (dump.Find(main, "aa.coverage") != nullptr) {
    std::optional<Buffer> dumpTriangles;
    if (!gbuffer) {
      dumpTriangles = UploadWords(dump, main, "raster.triangle", width, height, input);
      if (!dumpTriangles) throw InputError(input, "has aa.coverage without the layer raster.triangle it is made from");
    }
    if (!sceneBuffers) sceneBuffers.emplace(scene.scene);
    edgeCoverage =
        RunEdgeCoverage(frame, *sceneBuffers, gbuffer ? gbuffer->visibility.triangle : *dumpTriangles, words[2]);
  } else if (dump.Find(main, "mlaa.coverage") != nullptr) {
    mlaa = RunMlaa(frame, config.tonemap.exposureEv, result, oracleMlaa);
  }
  std::optional<Buffer> antialiased;
  if (dump.Find(main, "aa.result.R") != nullptr) {
    if (!edgeCoverage && !mlaa)
      throw InputError(input, "layer aa.result.R is there without the coverage words it was blended by");
    antialiased = RunAntialias(frame, Pick(oracleCoverage, edgeCoverage ? *edgeCoverage : mlaa->coverage), result);
  }
  if (const GLenum code = glGetError(); code != GL_NO_ERROR) {
    char text[64];
    std::snprintf(text, sizeof text, "OpenGL error 0x%04X", unsigned(code));
    throw GlError(text);
  }

  ExrFile out;
  // The dump's scene and settings, so that `ssgi passes` runs the oracle on the port's buffers.
  out.metadata = dump.metadata;
  const auto addLayer = [&](const std::string& name, const Buffer& buffer, bool isUint = false) {
    out.layers.push_back(ExrLayer{main, name, frame.width, frame.height, isUint, buffer.Download()});
  };
  if (gbuffer) {
    // The words and the oracle's decodes of them, as its dump has them.
    GBuffer planes = MakeGBuffer(frame.width, frame.height, frame.normalEncoding);
    for (int w = 0; w < 3; ++w) {
      const std::vector<uint32_t> values = words[size_t(w)].Download();
      for (size_t y = 0; y < height; ++y)
        std::copy_n(values.begin() + std::ptrdiff_t(y * width), width, planes.word[size_t(w)].MutableRow(y));
    }
    DumpSink sink;
    sink.AddGBufferWords(planes);
    AppendDumpLayers(sink, out);
    if (gbuffer->visibility.triangle.words() > 0) addLayer("raster.triangle", gbuffer->visibility.triangle, true);
    if (gbuffer->visibility.depthKey.words() > 0) addLayer("raster.depthKey", gbuffer->visibility.depthKey);
  }
  if (shadows) {
    Plane<uint32_t> term = MakePlane<uint32_t>(width, height, kShadowLit);
    const std::vector<uint32_t> values = word3->Download();
    for (size_t y = 0; y < height; ++y)
      std::copy_n(values.begin() + std::ptrdiff_t(y * width), width, term.MutableRow(y));
    DumpSink sink;
    sink.AddShadowTerm(term);
    AppendDumpLayers(sink, out);
    addLayer("shadow.visibility", *visibility);
  }
  addLayer("ssr.hitX", trace.hitX);
  addLayer("ssr.hitY", trace.hitY);
  addLayer("ssr.confidence", trace.confidence);
  addLayer("ssr.iterations", trace.iterations);
  const char* rgb[] = {"R", "G", "B"};
  // The three planes of `buffer` as the layers `prefix`R, G, B of part `part`.
  const auto addRgb = [&](const std::string& part, const std::string& prefix, const Buffer& buffer, int w, int h) {
    const std::vector<uint32_t> planes = buffer.Download();
    for (size_t c = 0; c < 3; ++c) out.layers.push_back(PlaneLayer(part, prefix + rgb[c], planes, c, w, h));
  };
  addRgb(main, "direct.", direct, frame.width, frame.height);
  if (sky) {
    addRgb(main, "sky.diffuse.", sky->diffuse, frame.width, frame.height);
    addLayer("sky.visibility", sky->visibility);
    if (sky->reflected) addRgb(main, "sky.reflected.", *sky->reflected, frame.width, frame.height);
    addRgb(main, "lit.", sky->lit, frame.width, frame.height);
  }
  if (bounce) {
    addRgb(main, "bounce.", bounce->bounce, frame.width, frame.height);
    addLayer("bounce.visibility", bounce->visibility);
  }
  addRgb(main, "ssr.reflected.", reflected, frame.width, frame.height);
  addRgb(main, "indirect.", composite.indirect, frame.width, frame.height);
  addRgb(main, "result.", composite.result, frame.width, frame.height);
  if (edgeCoverage) addLayer("aa.coverage", *edgeCoverage, true);
  if (mlaa) {
    addLayer("mlaa.luma", mlaa->luma);
    addLayer("mlaa.edges", mlaa->edges, true);
    addLayer("mlaa.weights", mlaa->weights, true);
    addLayer("mlaa.coverage", mlaa->coverage, true);
  }
  if (antialiased) addRgb(main, "aa.result.", *antialiased, frame.width, frame.height);
  // The other parts after the image's, in the dump's order.
  if (shadows && !oracleShadowMap) {
    const int resolution = config.shadowMap.resolution;
    out.layers.push_back(
        ExrLayer{"shadowmap", "depthKey", resolution, resolution, false, shadowMap->depthKey.Download()});
  }
  if (skyVolume) out.layers.push_back(std::move(*skyVolume));
  if (interreflectionLayers.size() == 3)
    for (ExrLayer& layer : interreflectionLayers) out.layers.push_back(std::move(layer));
  if (bounce) AddBounceHalfLayers(*bounce, (frame.width + 1) / 2, (frame.height + 1) / 2, out);
  for (size_t k = 0; k < frame.levels.size(); ++k) {
    const int w = int(frame.levels[k].width), h = int(frame.levels[k].height);
    out.layers.push_back(ExrLayer{"hiz." + std::to_string(k), "Y", w, h, false, hizLevels[k].Download()});
  }
  for (size_t k = 0; k < frame.levels.size(); ++k)
    addRgb("pyramid." + std::to_string(k), "", pyramidLevels[k], int(frame.levels[k].width), int(frame.levels[k].height));
  WriteExrFile(output, out);
  return 0;
}

}  // namespace
}  // namespace ssgi::port

int main(int argc, char** argv) {
  CLI::App app{"Runs the GLSL port of ssgi's passes on an ssgi dump's scene (tests/port/README.md)."};
  std::string scene, input, output;
  app.add_option("--scene", scene, "The scene the dump was rendered from. Default: the one the dump names.");
  app.add_option("input", input, "The oracle's dump (ssgi render --dump IN.exr).")->required();
  app.add_option("-o,--output", output, "The port's buffers, as an EXR with the dump's layer names.")->required();
  bool oracleInputs = false;
  std::string raster = "oracle";
  app.add_option("--raster", raster,
                 "Where the rasterized buffers (G-buffer words 0-2, the shadow map) come from: the dump (oracle), "
                 "or GL's rasterizer, with the G-buffer from a visibility pass and the oracle's resolve "
                 "(visibility) or from a conventional pass writing the words from interpolated varyings "
                 "(conventional). Default: oracle.")
      ->check(CLI::IsMember({"oracle", "visibility", "conventional"}));
  int subpixelBits = 8;
  app.add_option("--subpixel-bits", subpixelBits,
                 "With --raster visibility or conventional: the G-buffer's vertices snapped to this many sub-pixel "
                 "bits before GL's rasterizer snaps them to its 8, to emulate a coarser one. Default: 8.")
      ->check(CLI::Range(1, 8));
  app.add_flag("--oracle-inputs", oracleInputs,
               "Each pass reads the oracle's buffers of the passes before it where the dump holds them "
               "(direct.*, lit.*, the bounce's steps, hiz.L, pyramid.L, ssr.hitX/hitY/confidence, ssr.reflected.*), so "
               "each pass is checked alone; default: the port's own.");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    using ssgi::port::RasterSource;
    const RasterSource source = raster == "visibility"     ? RasterSource::kVisibility
                                : raster == "conventional" ? RasterSource::kConventional
                                                           : RasterSource::kOracle;
    return ssgi::port::Run(scene, input, output, oracleInputs, source, subpixelBits);
  } catch (const ssgi::InputError& e) {
    std::fprintf(stderr, "ssgi_gl_port: error: %s\n", e.what());
    return 1;
  } catch (const ssgi::port::GlError& e) {
    std::fprintf(stderr, "ssgi_gl_port: OpenGL: %s\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ssgi_gl_port: internal error: %s\n", e.what());
    return 3;
  }
}
