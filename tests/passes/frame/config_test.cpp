#include "passes/frame/config.h"

#include <catch2/catch.hpp>

#include "core/error.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;

FrameConfig Preset(std::string_view name) {
  FrameConfig config;
  ApplySetting(config, "quality", name);
  return config;
}

// The frame configuration of a scene file whose render block is `render` (JSON text).
FrameConfig ConfigFor(const test::ScratchDir& dir, const std::string& render) {
  test::WriteText(dir / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  test::WriteText(dir / "scene.json",
                  "{\n  \"objects\": [ { \"obj\": \"tri.obj\" } ],\n  \"render\": " + render + "\n}\n");
  return FrameConfigFromSceneFile(LoadSceneFile(dir / "scene.json"));
}

TEST_CASE("quality presets: high is the defaults and every knob grows from low to ultra", "[frame_config]") {
  const FrameConfig defaults;
  const FrameConfig high = Preset("high");
  CHECK(high.shadowMap.resolution == defaults.shadowMap.resolution);
  CHECK(high.ssrTrace.maxIterations == defaults.ssrTrace.maxIterations);
  CHECK(high.ssrCone.maxSamples == defaults.ssrCone.maxSamples);
  const char* order[] = {"low", "medium", "high", "ultra"};
  for (int i = 0; i + 1 < 4; ++i) {
    const FrameConfig a = Preset(order[i]), b = Preset(order[i + 1]);
    CAPTURE(i);
    CHECK(a.shadowMap.resolution <= b.shadowMap.resolution);
    CHECK(a.shadowMap.blockerSearchTaps <= b.shadowMap.blockerSearchTaps);
    CHECK(a.shadowFilter.maxRadiusPixels <= b.shadowFilter.maxRadiusPixels);
    CHECK(a.ssrTrace.maxIterations <= b.ssrTrace.maxIterations);
    CHECK(a.ssrCone.maxSamples <= b.ssrCone.maxSamples);
    CHECK(int(a.antialiasing != Antialiasing::kOff) <= int(b.antialiasing != Antialiasing::kOff));
  }
  CHECK(Preset("low").antialiasing == Antialiasing::kOff);
  CHECK(high.antialiasing == defaults.antialiasing);
  CHECK(Preset("low").ssrTrace.maxIterations == 8);
  CHECK(Preset("ultra").ssrTrace.maxIterations == 128);
  // A preset resets every knob any preset sets, so a later "high" undoes an earlier "low".
  FrameConfig config = Preset("low");
  ApplySetting(config, "quality", "high");
  CHECK(config.shadowMap.resolution == defaults.shadowMap.resolution);
  CHECK(config.ssrCone.maxSamples == defaults.ssrCone.maxSamples);
  CHECK_THROWS_AS(ApplySetting(config, "quality", "extreme"), InputError);
}

TEST_CASE("the settings table: every entry is complete and reads back what it writes", "[frame_config]") {
  for (const FrameSetting& s : FrameSettings()) {
    CAPTURE(s.name);
    CHECK(!s.name.empty());
    CHECK(!s.help.empty());
    CHECK(s.set);
    CHECK((s.inSceneFile || !s.option.empty()));
    CHECK(FindFrameSetting(s.name) == &s);
    if (!s.option.empty()) CHECK(s.option.substr(0, 2) == "--");
    if (s.kind == SettingKind::kChoice) CHECK(s.choices.size() >= 2);
    // Every value the sweep tries parses, and a setting that stores a value reads it back.
    for (std::string_view value : s.sweep) {
      FrameConfig config;
      ApplySetting(config, s.name, value);
      if (s.get) CHECK(FormatSettingValue(s.get(config)) == value);
    }
    if (s.get) {
      FrameConfig config;
      const std::string text = FormatSettingValue(s.get(config));
      ApplySetting(config, s.name, text);
      CHECK(FormatSettingValue(s.get(config)) == text);
    }
  }
  for (const QualityPreset& preset : QualityPresets())
    for (const auto& [knob, value] : preset.knobs) {
      CAPTURE(preset.name, knob);
      REQUIRE(FindFrameSetting(knob));
      FrameConfig config;
      ApplySetting(config, knob, value);
    }
}

TEST_CASE("settings from text: every kind parsed and range-checked with the problem named", "[frame_config]") {
  FrameConfig config;
  ApplySetting(config, "size", "640x480");
  CHECK(config.width == 640);
  CHECK(config.height == 480);
  ApplySetting(config, "shadow_map_size", "512");
  CHECK(config.shadowMap.resolution == 512);
  ApplySetting(config, "exposure_ev", "-1.5");
  CHECK(config.tonemap.exposureEv == -1.5f);
  ApplySetting(config, "background", "0.1,0.2,0.3");
  CHECK(config.environment.radiance == glm::vec3(0.1f, 0.2f, 0.3f));
  ApplySetting(config, "effects.shadows", "off");
  CHECK(config.shadows == EffectMode::kOff);
  ApplySetting(config, "shadow_filter", "sspcss");
  CHECK(config.shadowFilter.filter == ShadowFilter::kSspcss);
  ApplySetting(config, "normal_encoding", "xyz8");
  CHECK(config.normalEncoding == NormalEncoding::kXyz8);

  auto error = [](std::string_view name, std::string_view text) {
    FrameConfig c;
    return test::InputErrorOf([&] { ApplySetting(c, name, text); });
  };
  CHECK(error("ssr_iterations", "0") == "--ssr-iterations: must be in [1, 4096], got 0");
  CHECK(error("ssr_iterations", "12.5") == "--ssr-iterations: must be an integer, got 12.5");
  CHECK(error("ssr_iterations", "many") == "--ssr-iterations: must be an integer, got 'many'");
  CHECK(error("exposure_ev", "1e999") == "--exposure: must be a finite number, got 1e999");
  CHECK(error("exposure_ev", "nan") == "--exposure: must be a finite number, got nan");
  CHECK(error("background", "0.1,0.2") == "--background: must be three numbers R,G,B, got '0.1,0.2'");
  CHECK(error("background", "0.1,-1,0") == "--background: components must be >= 0, got '0.1,-1,0'");
  CHECK(error("tonemap", "filmic") == "--tonemap: must be one of aces, clamp, got 'filmic'");
  CHECK_THAT(error("size", "0x10"), Catch::Contains("--size") && Catch::Contains("[1, 16384]"));
  CHECK_THAT(error("size", "banana"), Catch::Contains("WIDTHxHEIGHT"));
  CHECK(error("width", "0") == "width: must be in [1, 16384], got 0");
  CHECK(error("no_such_knob", "1") == "no_such_knob: no such setting");
}

TEST_CASE("the bounce's settings: each set, and a bad value refused with one line", "[frame_config]") {
  FrameConfig config;
  CHECK(config.bounce == EffectMode::kAuto);
  ApplySetting(config, "effects.bounce", "off");
  CHECK(config.bounce == EffectMode::kOff);
  ApplySetting(config, "bounce_slices", "3");
  ApplySetting(config, "bounce_steps", "8");
  ApplySetting(config, "bounce_radius", "0.5");
  ApplySetting(config, "bounce_max_radius", "64");
  ApplySetting(config, "bounce_thickness", "0.1");
  CHECK(config.diffuseBounce.slices == 3);
  CHECK(config.diffuseBounce.steps == 8);
  CHECK(config.diffuseBounce.radius == 0.5f);
  CHECK(config.diffuseBounce.maxRadiusPixels == 64.0f);
  CHECK(config.diffuseBounce.thickness == 0.1f);
  auto error = [](std::string_view name, std::string_view text) {
    FrameConfig c;
    return test::InputErrorOf([&] { ApplySetting(c, name, text); });
  };
  CHECK(error("effects.bounce", "maybe") == "--bounce: must be one of auto, on, off, got 'maybe'");
  CHECK(error("bounce_slices", "0") == "--bounce-slices: must be in [1, 16], got 0");
  CHECK(error("bounce_slices", "17") == "--bounce-slices: must be in [1, 16], got 17");
  CHECK(error("bounce_steps", "33") == "--bounce-steps: must be in [1, 32], got 33");
  CHECK(error("bounce_steps", "2.5") == "--bounce-steps: must be an integer, got 2.5");
  CHECK(error("bounce_radius", "-1") == "--bounce-radius: must be >= 0, got -1");
  CHECK(error("bounce_radius", "inf") == "--bounce-radius: must be a finite number, got inf");
  CHECK(error("bounce_max_radius", "-0.5") == "--bounce-max-radius: must be >= 0, got -0.5");
  CHECK(error("bounce_thickness", "thick") == "--bounce-thickness: must be a number, got 'thick'");
  // In a scene file: "effects": {"bounce": false}, and the knobs by name.
  test::ScratchDir dir("frame-config-bounce");
  const FrameConfig file = ConfigFor(dir, R"({ "effects": { "bounce": false }, "bounce_steps": 16 })");
  CHECK(file.bounce == EffectMode::kOff);
  CHECK(file.diffuseBounce.steps == 16);
  CHECK_THAT(test::InputErrorOf([&] { ConfigFor(dir, R"({ "bounce_slices": 0 })"); }),
             Catch::Contains("render.bounce_slices must be in [1, 16], got 0"));
}

TEST_CASE("a scene file's render block sets the frame configuration", "[frame_config]") {
  test::ScratchDir dir("frame-config-render");
  const FrameConfig config = ConfigFor(dir, R"({ "width": 320, "height": 200, "exposure_ev": -1.5, "tonemap": "clamp",
    "background": [0.1, 0.2, 0.3], "normal_encoding": "xyz8", "effects": { "shadows": false, "reflections": "on" },
    "quality": "low", "ssr_iterations": 20, "shadow_filter": "hard" })");
  CHECK(config.width == 320);
  CHECK(config.height == 200);
  CHECK(config.tonemap.exposureEv == -1.5f);
  CHECK(config.tonemap.curve == Tonemap::kClamp);
  CHECK(config.environment.radiance == glm::vec3(0.1f, 0.2f, 0.3f));
  CHECK(config.normalEncoding == NormalEncoding::kXyz8);
  CHECK(config.shadows == EffectMode::kOff);
  CHECK(config.reflections == EffectMode::kOn);
  CHECK(config.shadowFilter.filter == ShadowFilter::kHard);
  CHECK(config.shadowMap.blockerSearchTaps == 4);  // the preset
  CHECK(config.ssrTrace.maxIterations == 20);  // the knob over the preset, whatever the key order
  // No render block: the defaults.
  const FrameConfig defaults = ConfigFor(dir, "{}");
  CHECK(defaults.width == kDefaultImageSide);
  CHECK(defaults.shadowMap.resolution == FrameConfig{}.shadowMap.resolution);
}

TEST_CASE("bad render blocks name the file, line and key", "[frame_config][errors]") {
  test::ScratchDir dir("frame-config-errors");
  auto errorFor = [&](const std::string& render) { return test::InputErrorOf([&] { ConfigFor(dir, render); }); };
  CHECK_THAT(errorFor("{\n  \"widht\": 5 }"),
             Catch::Contains("scene.json:4: unknown key render.widht (known: quality, width, height"));
  CHECK_THAT(errorFor(R"({ "size": "64x64" })"), Catch::Contains("unknown key render.size"));
  CHECK_THAT(errorFor(R"({ "width": "wide" })"),
             Catch::Contains("scene.json:3: render.width must be an integer, got \"wide\""));
  CHECK_THAT(errorFor(R"({ "width": 0 })"), Catch::Contains("render.width must be in [1, 16384], got 0"));
  CHECK_THAT(errorFor(R"({ "height": 20000 })"), Catch::Contains("render.height") && Catch::Contains("20000"));
  CHECK_THAT(errorFor(R"({ "effects": { "shadows": "maybe" } })"),
             Catch::Contains("render.effects.shadows must be one of auto, on, off, got \"maybe\""));
  CHECK_THAT(errorFor(R"({ "effects": { "shadows": 1 } })"),
             Catch::Contains("render.effects.shadows must be one of auto, on, off, true or false, got 1"));
  CHECK_THAT(errorFor(R"({ "effects": { "glow": "on" } })"), Catch::Contains("unknown key render.effects.glow"));
  CHECK_THAT(errorFor(R"({ "background": [0.1, 0.2] })"),
             Catch::Contains("render.background must be an array of 3 numbers"));
  CHECK_THAT(errorFor(R"({ "tonemap": "filmic" })"), Catch::Contains("render.tonemap must be one of aces, clamp"));
  CHECK_THAT(errorFor(R"({ "quality": "extreme" })"), Catch::Contains("render.quality must be one of low"));
  CHECK_THAT(errorFor(R"({ "blur_taps": 300 })"), Catch::Contains("render.blur_taps must be in [0, 256], got 300"));
  CHECK_THAT(errorFor(R"({ "exposure_ev": 1e300 })"), Catch::Contains("render.exposure_ev must be a finite number"));
}

}  // namespace
}  // namespace ssgi
