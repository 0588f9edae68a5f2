// How a frame is rendered (docs/design.md §12 "One configuration, one table"): FrameConfig holds every
// setting, and FrameSettings() declares each one once (name, help, valid values, default, setter).
// The command line's options, a scene file's "render" block, the sweep's knobs and the quality
// presets are all derived from that table, so a new knob is one entry there plus the code that
// uses it. What is rendered (camera, lights, objects) is the Scene (core/scene.h).
#pragma once

#include <functional>
#include <glm/glm.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "core/render_modes.h"
#include "core/scene.h"
#include "passes/bounce.h"
#include "passes/direct_light.h"
#include "passes/gbuffer.h"
#include "passes/shadow_filter.h"
#include "passes/shadow_map.h"
#include "passes/sky_light.h"
#include "passes/ssr_cone.h"
#include "passes/ssr_trace.h"
#include "passes/tonemap.h"
#include "passes/world_bounce.h"

namespace ssgi {

struct FrameConfig {
  int width = kDefaultImageSide;  // image size in pixels, [1, kMaxImageSize] each
  int height = kDefaultImageSide;
  NormalEncoding normalEncoding = NormalEncoding::kOct24;  // of G-buffer word 1
  float specularAaKappa = GBufferParams{}.specularAaKappa;  // G-buffer word 1's roughness widening
  EffectMode shadows = EffectMode::kAuto;
  EffectMode reflections = EffectMode::kAuto;
  EffectMode sky = EffectMode::kAuto;
  EffectMode bounce = EffectMode::kAuto;
  ShadowMapParams shadowMap;
  ShadowFilterParams shadowFilter;
  // The environment: the scene's, or a constant one of --background / render.background. The
  // direct light pass's `background` is set from it each frame (its mean radiance).
  Environment environment;
  DirectLightParams directLight;
  SkyVisibilityParams skyVisibility;
  WorldBounceParams interreflection;
  BounceParams diffuseBounce;
  SsrTraceParams ssrTrace;
  SsrConeParams ssrCone;
  Antialiasing antialiasing = Antialiasing::kEdge;  // of the final image (passes/antialias.h)
  TonemapParams tonemap;
};

// Whether the sky light, where it runs, makes the interreflection volume (passes/world_bounce.h):
// the light the surfaces send each other, on screen and off. The screen-space bounce in `auto` then
// does not run: measured against the full-transport reference, it changes the error by under 1% on
// top of the volume (docs/user-guide.md, "Against the full light transport") and costs more than the
// sky light.
inline bool SkyMakesInterreflection(const FrameConfig& config) {
  return config.skyVisibility.directions > 0 && config.interreflection.directions > 0;
}

struct ImageSize {
  int width = 0;
  int height = 0;
};
// A setting's value: a number (integers too), a name, a linear RGB colour or an image size.
using SettingValue = std::variant<double, std::string, glm::vec3, ImageSize>;

enum class SettingKind {
  kInteger,    // a whole number in [min, max]
  kNumber,     // a finite number in [min, max]
  kChoice,     // one of `choices`; in a scene file a string (an effect mode also true / false)
  kColor,      // linear RGB, each component in [min, max]; on the command line "R,G,B"
  kImageSize,  // "WIDTHxHEIGHT", each side in [1, kMaxImageSize]
};

struct FrameSetting {
  // The setting's key in a scene file's render block (dotted when nested: "effects.shadows"), the
  // sweep's knob name and the presets' name for it.
  std::string_view name;
  std::string_view option;  // `ssgi render`'s option ("--shadow-map-size"); "" = not on the command line
  bool inSceneFile = true;  // whether a render block may set it
  std::string_view help;
  SettingKind kind = SettingKind::kInteger;
  double min = 0.0, max = 0.0;            // kInteger, kNumber, kColor: the inclusive range
  std::vector<std::string_view> choices;  // kChoice: the names
  std::vector<std::string_view> sweep;    // the values ssgi_sweep tries, one row each; {} = not swept
  std::function<void(FrameConfig&, const SettingValue&)> set;
  std::function<SettingValue(const FrameConfig&)> get;  // the current value; empty: not stored as such
  // Whether `get` says what the configuration holds (empty: always); a dump records only those.
  std::function<bool(const FrameConfig&)> holdsValue = {};
};

// Every setting, in the order they are applied: "quality" first, so the knobs it sets can be
// overridden by the same source.
const std::vector<FrameSetting>& FrameSettings();
// The setting of that name, or null.
const FrameSetting* FindFrameSetting(std::string_view name);

// Parse a value as written on a command line or in the sweep and presets ("2048", "ssabss",
// "0.1,0.2,0.3", "640x480"), and check it against the setting's kind and range. Throw InputError
// whose message is the problem alone ("must be in [1, 4096], got 0"); callers add where it was.
SettingValue ParseSettingText(const FrameSetting& setting, std::string_view text);
// The same for a value of a scene file's render block, as JSON text.
SettingValue ParseSettingJson(const FrameSetting& setting, const std::string& json);
// The value as ParseSettingText reads it back.
std::string FormatSettingValue(const SettingValue& value);

// Sets one setting from text; throws InputError "<name>: <problem>" for an unknown name or a bad value.
void ApplySetting(FrameConfig& config, std::string_view name, std::string_view text);

// The defaults with a scene file's render block applied. Throws InputError(file, line, "render.<key>
// <problem>") for an unknown key or a bad value.
FrameConfig FrameConfigFromSceneFile(const SceneFile& file);

// Quality presets (docs/user-guide.md "Accuracy and time"), chosen from the sweep's measured Pareto fronts on
// the default scene and Sponza: each knob is cut where the time it saves costs least error. "high"
// is the defaults (the paper's settings, but for one cone sample instead of Uludag's 7 and 8
// blocker-search taps instead of 16, which the sweep measured less accurate); "ultra" adds what
// still lowered the error (the shadow map's resolution above all); knobs that bought nothing
// measurable stay at the defaults. Setting "quality" sets every knob any preset names, to the
// preset's value or the default.
struct QualityPreset {
  std::string_view name;
  std::vector<std::pair<std::string_view, std::string_view>> knobs;  // setting name, value
};
const std::vector<QualityPreset>& QualityPresets();

}  // namespace ssgi
