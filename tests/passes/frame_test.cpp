#include "passes/frame.h"

#include <catch2/catch.hpp>

#include "core/error.h"

namespace ssgi {
namespace {

TEST_CASE("quality presets: high is the defaults and every knob grows from low to ultra", "[frame]") {
  const FrameOptions defaults;
  const FrameOptions high = QualityPreset(Quality::kHigh);
  CHECK(high.shadowMap.resolution == defaults.shadowMap.resolution);
  CHECK(high.ssrTrace.maxIterations == defaults.ssrTrace.maxIterations);
  const Quality order[] = {Quality::kLow, Quality::kMedium, Quality::kHigh, Quality::kUltra};
  for (int i = 0; i + 1 < 4; ++i) {
    const FrameOptions a = QualityPreset(order[i]), b = QualityPreset(order[i + 1]);
    CAPTURE(i);
    CHECK(a.shadowMap.resolution <= b.shadowMap.resolution);
    CHECK(a.shadowMap.blockerSearchTaps <= b.shadowMap.blockerSearchTaps);
    CHECK(a.shadowFilter.maxRadiusPixels <= b.shadowFilter.maxRadiusPixels);
    CHECK(a.ssrTrace.maxIterations <= b.ssrTrace.maxIterations);
    CHECK(a.ssrCone.maxSamples <= b.ssrCone.maxSamples);
  }
  CHECK(ParseQuality("ultra") == Quality::kUltra);
  CHECK_THROWS_AS(ParseQuality("extreme"), InputError);
}

}  // namespace
}  // namespace ssgi
