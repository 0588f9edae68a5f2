#include "passes/frame/config.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace ssgi {
namespace {

using Json = nlohmann::json;
constexpr double kUnbounded = std::numeric_limits<double>::infinity();

std::string FormatNumber(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string RangeText(const FrameSetting& s) {
  if (s.max == kUnbounded && s.min == -kUnbounded) return "finite";
  if (s.max == kUnbounded) return ">= " + FormatNumber(s.min);
  return "in [" + FormatNumber(s.min) + ", " + FormatNumber(s.max) + "]";
}

std::string ChoicesText(const FrameSetting& s) {
  std::string text;
  for (std::string_view choice : s.choices) text.append(text.empty() ? "" : ", ").append(choice);
  return text;
}

double CheckNumber(const FrameSetting& s, double value, const std::string& written) {
  if (!std::isfinite(value) || !std::isfinite(float(value)))
    throw InputError("must be a finite number, got " + written);
  if (s.kind == SettingKind::kInteger && value != std::floor(value))
    throw InputError("must be an integer, got " + written);
  if (value < s.min || value > s.max) throw InputError("must be " + RangeText(s) + ", got " + written);
  return value;
}

std::string CheckChoice(const FrameSetting& s, const std::string& name, const std::string& written) {
  if (std::find(s.choices.begin(), s.choices.end(), name) == s.choices.end())
    throw InputError("must be one of " + ChoicesText(s) + ", got " + written);
  return name;
}

glm::vec3 CheckColor(const FrameSetting& s, const double (&c)[3], const std::string& written) {
  for (double v : c)
    if (!std::isfinite(float(v)) || v < s.min || v > s.max)
      throw InputError("components must be " + RangeText(s) + ", got " + written);
  return glm::vec3(float(c[0]), float(c[1]), float(c[2]));
}

// A whole text as one number ("12", "-1.5e3"), or nothing.
bool ParseNumber(std::string_view text, double& value) {
  const std::string copy(text);
  char* end = nullptr;
  value = std::strtod(copy.c_str(), &end);
  return !copy.empty() && end == copy.c_str() + copy.size() && !std::isspace(static_cast<unsigned char>(copy[0]));
}

bool IsEffectMode(const FrameSetting& s) {
  return s.kind == SettingKind::kChoice && s.choices == std::vector<std::string_view>{"auto", "on", "off"};
}

int ToInt(const SettingValue& v) { return int(std::get<double>(v)); }
float ToFloat(const SettingValue& v) { return float(std::get<double>(v)); }

// Setting and getting one member of the config, for the common kinds.
template <class Member>
FrameSetting IntegerSetting(std::string_view name, std::string_view option, std::string_view help, double min,
                            double max, std::vector<std::string_view> sweep, Member member) {
  FrameSetting s{name, option, true, help, SettingKind::kInteger, min, max, {}, std::move(sweep), {}, {}};
  s.set = [member](FrameConfig& c, const SettingValue& v) { member(c) = ToInt(v); };
  s.get = [member](const FrameConfig& c) { return SettingValue(double(member(c))); };
  return s;
}

template <class Member>
FrameSetting NumberSetting(std::string_view name, std::string_view option, std::string_view help, double min,
                           double max, std::vector<std::string_view> sweep, Member member) {
  FrameSetting s{name, option, true, help, SettingKind::kNumber, min, max, {}, std::move(sweep), {}, {}};
  s.set = [member](FrameConfig& c, const SettingValue& v) { member(c) = ToFloat(v); };
  s.get = [member](const FrameConfig& c) { return SettingValue(double(member(c))); };
  return s;
}

template <class Enum, class Member>
FrameSetting ChoiceSetting(std::string_view name, std::string_view option, std::string_view help,
                           std::vector<std::pair<std::string_view, Enum>> names, std::vector<std::string_view> sweep,
                           Member member) {
  FrameSetting s{name, option, true, help, SettingKind::kChoice, 0.0, 0.0, {}, std::move(sweep), {}, {}};
  for (const auto& entry : names) s.choices.push_back(entry.first);
  s.set = [names, member](FrameConfig& c, const SettingValue& v) {
    for (const auto& [n, value] : names)
      if (n == std::get<std::string>(v)) member(c) = value;
  };
  s.get = [names, member](const FrameConfig& c) {
    for (const auto& [n, value] : names)
      if (member(c) == value) return SettingValue(std::string(n));
    return SettingValue(std::string());
  };
  return s;
}

std::vector<FrameSetting> BuildFrameSettings() {
  std::vector<FrameSetting> table;
  {
    FrameSetting quality{
        "quality",
        "--quality",
        true,
        "Quality preset: low, medium, high (the default) or ultra (docs/user-guide.md 'Accuracy and time' gives "
        "each one's time and error). The quality knobs override it.",
        SettingKind::kChoice,
        0.0,
        0.0,
        {},
        {},
        {},
        {}};
    for (const QualityPreset& preset : QualityPresets()) quality.choices.push_back(preset.name);
    quality.set = [](FrameConfig& c, const SettingValue& v) {
      std::set<std::string_view> knobs;
      for (const QualityPreset& preset : QualityPresets())
        for (const auto& knob : preset.knobs) knobs.insert(knob.first);
      const FrameConfig defaults;
      for (std::string_view knob : knobs) {
        const FrameSetting& setting = *FindFrameSetting(knob);
        setting.set(c, setting.get(defaults));
      }
      for (const QualityPreset& preset : QualityPresets())
        if (preset.name == std::get<std::string>(v))
          for (const auto& [knob, value] : preset.knobs) ApplySetting(c, knob, value);
    };
    table.push_back(std::move(quality));
  }
  {
    FrameSetting size{"size", "--size", false, "Image size WIDTHxHEIGHT, each in [1, 16384]; overrides the scene's.",
                      SettingKind::kImageSize, 1.0, double(kMaxImageSize), {}, {}, {}, {}};
    size.set = [](FrameConfig& c, const SettingValue& v) {
      c.width = std::get<ImageSize>(v).width;
      c.height = std::get<ImageSize>(v).height;
    };
    size.get = [](const FrameConfig& c) { return SettingValue(ImageSize{c.width, c.height}); };
    table.push_back(std::move(size));
  }
  table.push_back(IntegerSetting("width", "", "Image width in pixels.", 1, kMaxImageSize, {},
                                 [](auto& c) -> auto& { return c.width; }));
  table.push_back(IntegerSetting("height", "", "Image height in pixels.", 1, kMaxImageSize, {},
                                 [](auto& c) -> auto& { return c.height; }));
  table.push_back(ChoiceSetting<NormalEncoding>(
      "normal_encoding", "--normal-encoding",
      "G-buffer normal encoding: oct24 (octahedral 2x12 bits) or xyz8 (3x8 bits, the paper's).",
      {{"oct24", NormalEncoding::kOct24}, {"xyz8", NormalEncoding::kXyz8}}, {"xyz8"},
      [](auto& c) -> auto& { return c.normalEncoding; }));
  table.push_back(NumberSetting(
      "specular_aa", "--specular-aa",
      "Specular anti-aliasing: the most the shading normal's variance over a pixel (curvature, a normal map's "
      "filtered texels) may add to GGX alpha^2 = roughness^4, so a highlight does not sparkle where the normal "
      "turns faster than a pixel (Kaplanyan et al. 2016's kappa; 0 = off, the default, 0.18 Tokuyoshi & Kaplanyan's "
      "bound). It steadies highlights, but against a supersampled truth it measures worse on screen (README "
      "'Anti-aliasing').",
      0.0, 1.0, {"0", "0.05", "0.5"}, [](auto& c) -> auto& { return c.specularAaKappa; }));
  const std::vector<std::pair<std::string_view, EffectMode>> effectModes = {
      {"auto", EffectMode::kAuto}, {"on", EffectMode::kOn}, {"off", EffectMode::kOff}};
  table.push_back(ChoiceSetting<EffectMode>(
      "effects.shadows", "--shadows", "Shadows: auto (when a light casts them), on or off.", effectModes, {},
      [](auto& c) -> auto& { return c.shadows; }));
  table.push_back(ChoiceSetting<EffectMode>(
      "effects.reflections", "--reflections",
      "Screen-space reflections (indirect light): auto (when a surface is smooth enough to reflect), on or off.",
      effectModes, {}, [](auto& c) -> auto& { return c.reflections; }));
  table.push_back(ChoiceSetting<EffectMode>(
      "effects.sky", "--sky",
      "Sky light: the environment's light on every surface, diffuse and (where the reflections do not "
      "reach) specular, under a world-space sky visibility, and the light the surfaces send each other from its interreflection "
      "volume: auto (when the environment is not black, or lights reach visible surfaces and the volume is made), on "
      "or off.",
      effectModes, {}, [](auto& c) -> auto& { return c.sky; }));
  table.push_back(ChoiceSetting<EffectMode>(
      "effects.bounce", "--bounce",
      "Diffuse bounce and ambient occlusion (screen-space visibility bitmask): the lit image's light bounced once "
      "onto diffuse surfaces, and the sky's diffuse light darkened where nearby surfaces cover the sky: auto (when "
      "something on screen is lit: a light reaches a visible pixel or the sky light runs, and no interreflection "
      "volume carries the bounced light), on or off.",
      effectModes, {}, [](auto& c) -> auto& { return c.bounce; }));
  table.push_back(IntegerSetting(
      "sky_directions", "--sky-directions",
      "Directions over the sphere of the sky visibility volume's depth maps, made once per scene: what blocks "
      "the sky off screen (0 = none: the sky reaches every surface the screen does not show blocked).",
      0, 1024, {"0", "16", "96"}, [](auto& c) -> auto& { return c.skyVisibility.directions; }));
  table.push_back(IntegerSetting(
      "interreflection_directions", "--interreflection-directions",
      "Rays from each cell of the sky visibility volume's grid that find the surfaces around it, made once per "
      "scene and lights: the scene's light interreflected off screen, which the sky light adds to every surface "
      "(0 = none; needs the sky visibility volume).",
      0, 1024, {"0", "32", "128"}, [](auto& c) -> auto& { return c.interreflection.directions; }));
  table.push_back(IntegerSetting(
      "sky_cells", "--sky-cells", "Cells of the sky visibility volume along the scene's longest side.", 4, 512,
      {"16", "32", "96"}, [](auto& c) -> auto& { return c.skyVisibility.cellsOnLongestAxis; }));
  table.push_back(ChoiceSetting<ShadowFilter>(
      "shadow_filter", "--shadow-filter",
      "Soft-shadow filter: ssabss (anisotropic, Zheng & Saito), sspcss (isotropic screen-space PCSS, "
      "MohammadBagher et al. 2010) or hard (the shadow map's hard test).",
      {{"ssabss", ShadowFilter::kSsabss}, {"sspcss", ShadowFilter::kSspcss}, {"hard", ShadowFilter::kHard}},
      {"hard", "sspcss"}, [](auto& c) -> auto& { return c.shadowFilter.filter; }));
  table.push_back(IntegerSetting("shadow_map_size", "--shadow-map-size", "Shadow map resolution in texels per side.",
                                 16, kMaxImageSize, {"512", "1024", "4096"},
                                 [](auto& c) -> auto& { return c.shadowMap.resolution; }));
  table.push_back(IntegerSetting("blocker_taps", "--blocker-taps", "PCSS blocker-search taps per pixel.", 1,
                                 kMaxBlockerSearchTaps, {"4", "16", "32"},
                                 [](auto& c) -> auto& { return c.shadowMap.blockerSearchTaps; }));
  table.push_back(IntegerSetting("blur_radius", "--blur-radius", "Shadow blur radius clamp in pixels.", 0, 256,
                                 {"8", "48"}, [](auto& c) -> auto& { return c.shadowFilter.maxRadiusPixels; }));
  table.push_back(IntegerSetting("blur_taps", "--blur-taps",
                                 "Shadow blur taps per side of each 1-D pass (0 = one per pixel of the radius).", 0,
                                 256, {"2", "4", "8"}, [](auto& c) -> auto& { return c.shadowFilter.taps; }));
  table.push_back(IntegerSetting("ssr_iterations", "--ssr-iterations", "Hi-Z steps per reflected ray.", 1, 4096,
                                 {"8", "16", "32", "128"},
                                 [](auto& c) -> auto& { return c.ssrTrace.maxIterations; }));
  table.push_back(IntegerSetting("hiz_start_level", "--hiz-start-level",
                                 "Hi-Z level a reflected ray continues at after leaving its own pixel (higher levels "
                                 "stride faster through open space; clamped to the top level).",
                                 0, 30, {"0", "2", "4"}, [](auto& c) -> auto& { return c.ssrTrace.startLevel; }));
  table.push_back(NumberSetting(
      "ssr_quad_roughness", "--ssr-quad-roughness",
      "Reflections: from this roughness up, a pixel shares the reflected ray of its 2x2 quad's top-left pixel on "
      "the same surface (its own cone widens the shared hit); at or above the trace's cut-off (0.7), every pixel "
      "traces its own.",
      0.0, 1.0, {"0", "0.1", "0.3", "1"}, [](auto& c) -> auto& { return c.ssrTrace.quadRoughness; }));
  table.push_back(NumberSetting(
      "ssr_block_roughness", "--ssr-block-roughness",
      "Reflections: from this roughness up, a pixel shares the ray of its 4x4 block's top-left pixel instead.", 0.0,
      1.0, {"0.1", "0.3", "0.5", "1"}, [](auto& c) -> auto& { return c.ssrTrace.blockRoughness; }));
  table.push_back(IntegerSetting("cone_samples", "--cone-samples", "Colour-pyramid samples per cone.", 1, 64,
                                 {"3", "7", "12"}, [](auto& c) -> auto& { return c.ssrCone.maxSamples; }));
  table.push_back(IntegerSetting(
      "bounce_slices", "--bounce-slices", "Diffuse bounce: slice directions per pixel, each marched both ways.", 1,
      kBounceMaxSlices, {"1", "3", "4"}, [](auto& c) -> auto& { return c.diffuseBounce.slices; }));
  table.push_back(IntegerSetting(
      "bounce_steps", "--bounce-steps", "Diffuse bounce: depth samples per slice direction.", 1, kBounceMaxSteps,
      {"2", "8", "16"}, [](auto& c) -> auto& { return c.diffuseBounce.steps; }));
  table.push_back(NumberSetting(
      "bounce_radius", "--bounce-radius", "Diffuse bounce: search radius in metres around each pixel (view space).",
      0.0, kUnbounded, {"0.5", "2"}, [](auto& c) -> auto& { return c.diffuseBounce.radius; }));
  table.push_back(NumberSetting(
      "bounce_max_radius", "--bounce-max-radius",
      "Diffuse bounce: the search radius's cap in pixels, however near the surface.", 0.0, kUnbounded, {"64", "256"},
      [](auto& c) -> auto& { return c.diffuseBounce.maxRadiusPixels; }));
  table.push_back(NumberSetting(
      "bounce_thickness", "--bounce-thickness",
      "Diffuse bounce: the thickness in metres taken behind every surface the camera sees "
      "(light passes behind it).",
      0.0, kUnbounded, {"0.1", "1"}, [](auto& c) -> auto& { return c.diffuseBounce.thickness; }));
  {
    FrameSetting exposure{"exposure_ev", "--exposure", true, "Exposure in EV (image x 2^EV before the tonemap).",
                          SettingKind::kNumber, -kUnbounded, kUnbounded, {}, {}, {}, {}};
    exposure.set = [](FrameConfig& c, const SettingValue& v) { c.tonemap.exposureEv = ToFloat(v); };
    exposure.get = [](const FrameConfig& c) { return SettingValue(double(c.tonemap.exposureEv)); };
    table.push_back(std::move(exposure));
  }
  table.push_back(ChoiceSetting<Antialiasing>(
      "antialiasing", "--aa",
      "Anti-aliasing of the final image, blended in linear HDR before the tonemap: edge (each geometric "
      "edge's coverage of the pixels it crosses, from the rasterizer's triangles), mlaa (morphological: the "
      "edges of the image's luma, followed along their runs, and the coverage of the silhouette their ends "
      "outline) or off.",
      {{"off", Antialiasing::kOff}, {"edge", Antialiasing::kEdge}, {"mlaa", Antialiasing::kMlaa}},
      {"off", "edge", "mlaa"}, [](auto& c) -> auto& { return c.antialiasing; }));
  table.push_back(ChoiceSetting<Tonemap>("tonemap", "--tonemap",
                                         "Display curve of PNG output: aces (Narkowicz's filmic fit) or clamp.",
                                         {{"aces", Tonemap::kAces}, {"clamp", Tonemap::kClamp}}, {},
                                         [](auto& c) -> auto& { return c.tonemap.curve; }));
  {
    FrameSetting background{"background",
                            "--background",
                            true,
                            "The constant environment's linear RGB radiance, as R,G,B: seen where no geometry "
                            "covers a pixel, and lighting every surface in the reference. Overrides the scene "
                            "file's environment.",
                            SettingKind::kColor,
                            0.0,
                            kUnbounded,
                            {},
                            {},
                            {},
                            {}};
    background.set = [](FrameConfig& c, const SettingValue& v) {
      c.environment = ConstantEnvironment(std::get<glm::vec3>(v));
    };
    background.get = [](const FrameConfig& c) { return SettingValue(c.environment.radiance); };
    // A sky or an image comes from the scene file, which a dump names: only a constant one is a value.
    background.holdsValue = [](const FrameConfig& c) { return c.environment.kind == EnvironmentKind::kConstant; };
    table.push_back(std::move(background));
  }
  return table;
}

}  // namespace

const std::vector<QualityPreset>& QualityPresets() {
  static const std::vector<QualityPreset> presets = {
      {"low",
       {{"blocker_taps", "4"},
        {"blur_taps", "2"},
        {"ssr_iterations", "8"},
        {"ssr_block_roughness", "0.1"},
        {"antialiasing", "off"}}},
      {"medium", {{"blur_taps", "4"}, {"ssr_iterations", "32"}}},
      {"high", {}},
      {"ultra",
       {{"shadow_map_size", "4096"},
        {"ssr_iterations", "128"},
        {"ssr_quad_roughness", "1"},
        {"ssr_block_roughness", "1"}}},
  };
  return presets;
}

const std::vector<FrameSetting>& FrameSettings() {
  static const std::vector<FrameSetting> table = BuildFrameSettings();
  return table;
}

const FrameSetting* FindFrameSetting(std::string_view name) {
  for (const FrameSetting& s : FrameSettings())
    if (s.name == name) return &s;
  return nullptr;
}

SettingValue ParseSettingText(const FrameSetting& s, std::string_view text) {
  const std::string written = "'" + std::string(text) + "'";
  switch (s.kind) {
    case SettingKind::kInteger:
    case SettingKind::kNumber: {
      double value = 0.0;
      if (!ParseNumber(text, value))
        throw InputError(std::string(s.kind == SettingKind::kInteger ? "must be an integer" : "must be a number") +
                         ", got " + written);
      return CheckNumber(s, value, std::string(text));
    }
    case SettingKind::kChoice:
      return CheckChoice(s, std::string(text), written);
    case SettingKind::kColor: {
      double c[3];
      std::string_view rest = text;
      for (int i = 0; i < 3; ++i) {
        const size_t comma = i < 2 ? rest.find(',') : std::string_view::npos;
        if ((i < 2 && comma == std::string_view::npos) || !ParseNumber(rest.substr(0, comma), c[i]))
          throw InputError("must be three numbers R,G,B, got " + written);
        rest = i < 2 ? rest.substr(comma + 1) : std::string_view();
      }
      return CheckColor(s, c, written);
    }
    case SettingKind::kImageSize: {
      ImageSize size;
      ParseImageSize(std::string(text), size.width, size.height);
      return size;
    }
  }
  throw InputError("has an unknown kind");
}

SettingValue ParseSettingJson(const FrameSetting& s, const std::string& json) {
  const Json value = Json::parse(json);
  switch (s.kind) {
    case SettingKind::kInteger:
      if (!value.is_number_integer()) throw InputError("must be an integer, got " + json);
      return CheckNumber(s, value.get<double>(), json);
    case SettingKind::kNumber:
      if (!value.is_number()) throw InputError("must be a number, got " + json);
      return CheckNumber(s, value.get<double>(), json);
    case SettingKind::kChoice:
      if (IsEffectMode(s) && value.is_boolean()) return std::string(value.get<bool>() ? "on" : "off");
      if (!value.is_string())
        throw InputError("must be one of " + ChoicesText(s) + (IsEffectMode(s) ? ", true or false" : "") + ", got " +
                         json);
      return CheckChoice(s, value.get<std::string>(), json);
    case SettingKind::kColor: {
      if (!value.is_array() || value.size() != 3) throw InputError("must be an array of 3 numbers, got " + json);
      double c[3];
      for (size_t i = 0; i < 3; ++i) {
        if (!value[i].is_number()) throw InputError("must be an array of 3 numbers, got " + json);
        c[i] = value[i].get<double>();
      }
      return CheckColor(s, c, json);
    }
    case SettingKind::kImageSize:
      if (!value.is_string()) throw InputError("must be a string WIDTHxHEIGHT, got " + json);
      return ParseSettingText(s, value.get<std::string>());
  }
  throw InputError("has an unknown kind");
}

std::string FormatSettingValue(const SettingValue& value) {
  if (const double* number = std::get_if<double>(&value)) return FormatNumber(*number);
  if (const std::string* name = std::get_if<std::string>(&value)) return *name;
  if (const glm::vec3* c = std::get_if<glm::vec3>(&value))
    return FormatNumber(c->x) + "," + FormatNumber(c->y) + "," + FormatNumber(c->z);
  const ImageSize& size = std::get<ImageSize>(value);
  return std::to_string(size.width) + "x" + std::to_string(size.height);
}

void ApplySetting(FrameConfig& config, std::string_view name, std::string_view text) {
  const FrameSetting* setting = FindFrameSetting(name);
  if (!setting) throw InputError(std::string(name) + ": no such setting");
  try {
    setting->set(config, ParseSettingText(*setting, text));
  } catch (const InputError& e) {
    throw InputError(std::string(setting->option.empty() ? name : setting->option) + ": " + e.what());
  }
}

FrameConfig FrameConfigFromSceneFile(const SceneFile& file) {
  const std::filesystem::path& path = file.scene.source;
  std::string known;
  for (const FrameSetting& s : FrameSettings())
    if (s.inSceneFile) known.append(known.empty() ? "" : ", ").append(s.name);
  for (const RenderBlockEntry& entry : file.render) {
    const FrameSetting* setting = FindFrameSetting(entry.key);
    if (!setting || !setting->inSceneFile)
      throw InputError(path, entry.line, "unknown key render." + entry.key + " (known: " + known + ")");
  }
  FrameConfig config;
  // The scene's environment, unless its render block says otherwise.
  config.environment = file.scene.environment;
  for (const FrameSetting& setting : FrameSettings()) {
    for (const RenderBlockEntry& entry : file.render) {
      if (entry.key != setting.name) continue;
      try {
        setting.set(config, ParseSettingJson(setting, entry.json));
      } catch (const InputError& e) {
        throw InputError(path, entry.line, "render." + entry.key + " " + e.what());
      }
    }
  }
  return config;
}

}  // namespace ssgi
