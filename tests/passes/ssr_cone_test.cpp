#include "passes/ssr_cone.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "core/parallel.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

constexpr size_t kStepWidth = 256, kStepHeight = 64;
constexpr float kStepEdge = 128.0f;   // level-0 columns x < 128 are 0, the rest 1
constexpr float kConeHeight = 24.0f;  // px from each origin straight up to its hit

ColorPyramid StepPyramid() {
  Plane3<float> image = MakePlane3<float>(kStepWidth, kStepHeight, 0.0f);
  for (Plane<float>& channel : image.c) {
    for (size_t y = 0; y < kStepHeight; ++y) {
      for (size_t x = size_t(kStepEdge); x < kStepWidth; ++x) channel.MutableRow(y)[x] = 1.0f;
    }
  }
  ColorPyramid pyramid;
  RunColorPyramid(image, pyramid);
  return pyramid;
}

GBuffer UniformRoughness(size_t width, size_t height, uint32_t code) {
  GBuffer gbuffer = MakeGBuffer(int(width), int(height), NormalEncoding::kOct24);
  for (size_t y = 0; y < height; ++y) {
    for (size_t x = 0; x < width; ++x) gbuffer.word[GBufferWord::kNormalRoughness].MutableRow(y)[x] = code << 24;
  }
  return gbuffer;
}

// Every pixel hits kConeHeight px above itself (clamped into the image), offset by hitOffsetX, so
// the cone walks along the step edge and the reflected row shows the edge blurred by the cone only.
SsrTraceOutputs VerticalHits(float hitOffsetX) {
  SsrTraceOutputs trace{MakePlane<float>(kStepWidth, kStepHeight, 0.0f),
                        MakePlane<float>(kStepWidth, kStepHeight, 0.0f),
                        MakePlane<float>(kStepWidth, kStepHeight, 1.0f), {}};
  for (size_t y = 0; y < kStepHeight; ++y) {
    for (size_t x = 0; x < kStepWidth; ++x) {
      trace.hitX.MutableRow(y)[x] = float(x) + 0.5f + hitOffsetX;
      trace.hitY.MutableRow(y)[x] = std::max(float(y) + 0.5f - kConeHeight, 0.5f);
    }
  }
  return trace;
}

SsrConeOutputs Cone(const GBuffer& gbuffer, const ColorPyramid& pyramid, const SsrTraceOutputs& trace,
                    SsrConeStats* stats = nullptr) {
  SsrConeOutputs out;
  const SsrConeStats s = RunSsrCone({gbuffer, pyramid, trace.hitX, trace.hitY, trace.confidence}, SsrConeParams{}, out);
  if (stats) *stats = s;
  return out;
}

// 10-90 % width (px) of the rising edge in row y, thresholds relative to the row's min and max.
float EdgeWidth(const Plane<float>& plane, size_t y) {
  const float* row = plane.ConstRow(y);
  const float lo = *std::min_element(row, row + plane.xsize());
  const float hi = *std::max_element(row, row + plane.xsize());
  const auto crossing = [&](float fraction) {
    const float level = lo + fraction * (hi - lo);
    for (size_t x = 1; x < plane.xsize(); ++x) {
      if (row[x] >= level) return float(x - 1) + (level - row[x - 1]) / (row[x] - row[x - 1]);
    }
    return float(plane.xsize());
  };
  return crossing(0.9f) - crossing(0.1f);
}

bool AllFiniteNonNegative(const Plane3<float>& image) {
  for (const Plane<float>& channel : image.c) {
    for (size_t y = 0; y < channel.ysize(); ++y) {
      for (size_t x = 0; x < channel.xsize(); ++x) {
        const float v = channel.ConstRow(y)[x];
        if (!std::isfinite(v) || v < 0.0f) return false;
      }
    }
  }
  return true;
}

TEST_CASE("Cone half-angle table is monotone, Uludag's at the ends", "[cone]") {
  const ConeTanTable table = BuildConeTanTable();
  for (size_t code = 1; code < 256; ++code) CHECK(table[code] >= table[code - 1]);
  CHECK(table[0] > 0.0f);
  CHECK(table[0] < 2e-3f);                                        // n = 1e6: a near-mirror
  CHECK(table[255] == Approx(std::tan(std::acos(0.244))).epsilon(1e-6));  // n = 0
  CHECK(ConeHalfAngleTan(128) == table[128]);
}

TEST_CASE("Roughness code 0 reflects the level-0 bilinear sample at the hit", "[cone]") {
  const ColorPyramid pyramid = StepPyramid();
  const float offset = 0.3f;  // hits between texel centres, so bilinear weights are exercised
  const SsrConeOutputs out = Cone(UniformRoughness(kStepWidth, kStepHeight, 0), pyramid, VerticalHits(offset));
  const size_t y = 40;
  const Plane<float>& level0 = pyramid.levels[0].c[0];
  size_t edgePixels = 0;
  for (size_t x = 0; x + 1 < kStepWidth; ++x) {
    // Hit at x + 0.8: 70 % texel x, 30 % texel x + 1.
    const float expected = 0.7f * level0.ConstRow(y - 24)[x] + 0.3f * level0.ConstRow(y - 24)[x + 1];
    CHECK(out.reflected.c[0].ConstRow(y)[x] == Approx(expected).margin(1e-6));
    if (expected > 0.0f && expected < 1.0f) ++edgePixels;
  }
  CHECK(edgePixels == 1);  // the step stays one pixel sharp
}

TEST_CASE("Cone reflection blur widens with roughness", "[cone]") {
  const ColorPyramid pyramid = StepPyramid();
  const SsrTraceOutputs trace = VerticalHits(0.0f);
  std::vector<int> codes;
  for (int code = 0; code < 256; code += 32) codes.push_back(code);
  codes.push_back(255);
  std::vector<float> widths;
  for (int code : codes) {
    const SsrConeOutputs out = Cone(UniformRoughness(kStepWidth, kStepHeight, uint32_t(code)), pyramid, trace);
    widths.push_back(EdgeWidth(out.reflected.c[0], 40));
    INFO("code " << code << " width " << widths.back());
    CHECK(std::isfinite(widths.back()));
  }
  for (size_t i = 1; i < widths.size(); ++i) {
    INFO("code " << codes[i] << ": " << widths[i] << " after " << widths[i - 1]);
    CHECK(widths[i] >= widths[i - 1]);
  }
  CHECK(widths.back() > widths.front() + 8.0f);
}

// The pyramid of a width x height image of random radiance in [0, 100].
ColorPyramid RandomPyramid(size_t width, size_t height, std::mt19937& rng) {
  Plane3<float> image = MakePlane3<float>(width, height, 0.0f);
  std::uniform_real_distribution<float> radiance(0.0f, 100.0f);
  for (Plane<float>& channel : image.c) {
    for (size_t y = 0; y < height; ++y) {
      for (size_t x = 0; x < width; ++x) channel.MutableRow(y)[x] = radiance(rng);
    }
  }
  ColorPyramid pyramid;
  RunColorPyramid(image, pyramid);
  return pyramid;
}

// The positions of the four corner pixels of a width x height image nearest its corners.
std::vector<std::pair<float, float>> Corners(size_t width, size_t height) {
  const float w = std::nextafter(float(width), 0.0f), h = std::nextafter(float(height), 0.0f);
  return {{0.0f, 0.0f}, {w, 0.0f}, {0.0f, h}, {w, h}};
}

const std::vector<std::pair<size_t, size_t>> kOddSizes{{1, 1}, {67, 45}, {1, 9}, {33, 2}};

TEST_CASE("Cone trace is finite for every code, h = 0, corners and a 1x1 image", "[cone]") {
  std::mt19937 rng(7);
  for (const auto& [width, height] : kOddSizes) {
    const ColorPyramid pyramid = RandomPyramid(width, height, rng);
    // Hits: the pixel itself (h = 0), the four image corners, and random points.
    const float w = float(width), h = float(height);
    const std::vector<std::pair<float, float>> corners = Corners(width, height);
    std::uniform_real_distribution<float> hitX(0.0f, std::nextafter(w, 0.0f)), hitY(0.0f, std::nextafter(h, 0.0f));
    for (int pattern = 0; pattern < 6; ++pattern) {
      SsrTraceOutputs trace{MakePlane<float>(width, height, 0.0f), MakePlane<float>(width, height, 0.0f),
                            MakePlane<float>(width, height, 1.0f), {}};
      for (size_t y = 0; y < height; ++y) {
        for (size_t x = 0; x < width; ++x) {
          std::pair<float, float> hit{float(x) + 0.5f, float(y) + 0.5f};
          if (pattern >= 1 && pattern <= 4) hit = corners[size_t(pattern - 1)];
          if (pattern == 5) hit = {hitX(rng), hitY(rng)};
          trace.hitX.MutableRow(y)[x] = hit.first;
          trace.hitY.MutableRow(y)[x] = hit.second;
        }
      }
      for (uint32_t code = 0; code < 256; ++code) {
        SsrConeStats stats;
        const SsrConeOutputs out = Cone(UniformRoughness(width, height, code), pyramid, trace, &stats);
        INFO(width << "x" << height << " pattern " << pattern << " code " << code);
        REQUIRE(AllFiniteNonNegative(out.reflected));
        CHECK(stats.pixels == width * height);
        CHECK(stats.samples >= stats.pixels);
        CHECK(stats.samples <= stats.pixels * size_t(SsrConeParams{}.maxSamples));
      }
    }
  }
}

TEST_CASE("Cone trace: the pyramid texels it reads are listed, and a pyramid of only those gives its bytes",
          "[cone][plan]") {
  const ColorPyramid whole = StepPyramid();
  const SsrTraceOutputs trace = VerticalHits(0.37f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const uint32_t code : {0u, 1u, 77u, 200u, 255u}) {
    CAPTURE(code);
    const GBuffer gbuffer = UniformRoughness(kStepWidth, kStepHeight, code);
    const std::optional<ColorPyramidNeeds> needs =
        SsrConePyramidNeeds(gbuffer.word[GBufferWord::kNormalRoughness], trace.hitX, trace.hitY, trace.confidence,
                            nullptr, size_t(1) << 30);
    REQUIRE(needs);
    size_t texels = 0;
    for (const std::vector<ColumnSpan>& level : needs->rows)
      for (const ColumnSpan& span : level) texels += span.Empty() ? 0 : size_t(span.end - span.begin);
    CHECK((code == 0) == (texels == 0));  // the mirror reads level 0 only
    // Every texel not listed (nor made from a listed one) NaN: a cone reading one would differ.
    ColorPyramid partial;
    for (const Plane3<float>& level : whole.levels)
      partial.levels.push_back(MakePlane3<float>(level.c[0].xsize(), level.c[0].ysize(), nan));
    partial.levels[0] = test::CopyOf(whole.levels[0]);
    RunColorPyramidOnLevelZero(partial, KernelPath::kSimd, &*needs);
    for (const KernelPath kernels : {KernelPath::kScalar, KernelPath::kSimd}) {
      SsrConeOutputs expected, actual;
      const SsrConeInputs fromWhole{gbuffer, whole, trace.hitX, trace.hitY, trace.confidence};
      const SsrConeInputs fromPartial{gbuffer, partial, trace.hitX, trace.hitY, trace.confidence};
      RunSsrCone(fromWhole, SsrConeParams{}, expected, kernels);
      RunSsrCone(fromPartial, SsrConeParams{}, actual, kernels);
      for (int c = 0; c < 3; ++c) CHECK(test::SameBytes(actual.reflected.c[c], expected.reflected.c[c]));
    }
    // Past the limit on listed row spans: none, so the whole pyramid is made.
    if (code != 0) {
      CHECK_FALSE(SsrConePyramidNeeds(gbuffer.word[GBufferWord::kNormalRoughness], trace.hitX, trace.hitY,
                                      trace.confidence, nullptr, 10));
    }
  }
}

TEST_CASE("Cone output is 0 where the trace has no hit", "[cone]") {
  const ColorPyramid pyramid = StepPyramid();
  SsrTraceOutputs trace = VerticalHits(0.0f);
  trace.hitX.MutableRow(10)[200] = -1.0f;
  trace.hitY.MutableRow(10)[200] = -1.0f;
  trace.confidence.MutableRow(10)[200] = 0.0f;
  SsrConeStats stats;
  const SsrConeOutputs out = Cone(UniformRoughness(kStepWidth, kStepHeight, 100), pyramid, trace, &stats);
  for (const Plane<float>& channel : out.reflected.c) CHECK(channel.ConstRow(10)[200] == 0.0f);
  CHECK(out.reflected.c[0].ConstRow(10)[201] > 0.0f);
  CHECK(stats.pixels == kStepWidth * kStepHeight - 1);
}

TEST_CASE("Cone output is byte-identical at 1, 2 and 3 threads", "[cone]") {
  const ColorPyramid pyramid = StepPyramid();
  const SsrTraceOutputs trace = VerticalHits(0.37f);
  GBuffer gbuffer = MakeGBuffer(int(kStepWidth), int(kStepHeight), NormalEncoding::kOct24);
  for (size_t y = 0; y < kStepHeight; ++y) {
    for (size_t x = 0; x < kStepWidth; ++x)
      gbuffer.word[GBufferWord::kNormalRoughness].MutableRow(y)[x] = uint32_t((x * 7 + y * 13) & 255) << 24;
  }
  std::vector<std::vector<float>> results;
  for (int threads : {1, 2, 3}) {
    const ThreadLimit limit(threads);
    const SsrConeOutputs out = Cone(gbuffer, pyramid, trace);
    std::vector<float> flat;
    for (const Plane<float>& channel : out.reflected.c) {
      for (size_t y = 0; y < kStepHeight; ++y) {
        flat.insert(flat.end(), channel.ConstRow(y), channel.ConstRow(y) + kStepWidth);
      }
    }
    results.push_back(std::move(flat));
  }
  CHECK(std::memcmp(results[0].data(), results[1].data(), results[0].size() * sizeof(float)) == 0);
  CHECK(std::memcmp(results[0].data(), results[2].data(), results[0].size() * sizeof(float)) == 0);
}

// SsrConeRowSimd against SsrConeRowScalar on every compiled and supported target, every row of the
// image whole, as its first 1 .. 49 pixels (three AVX-512 vectors and one lane) and as the runs from
// x = 32 (a tile mask's runs start on tile edges): same bits, nothing written outside the run, same
// counts.
void CheckConeRowTwins(const GBuffer& gbuffer, const ColorPyramid& pyramid, const SsrTraceOutputs& trace,
                       int maxSamples) {
  const ConeTanTable coneTan = BuildConeTanTable();
  const SsrConeContext context{pyramid, coneTan, maxSamples};
  const size_t width = size_t(gbuffer.width()), height = size_t(gbuffer.height());
  struct Segment {
    size_t y, begin, end;
  };
  std::vector<Segment> segments;
  for (size_t y = 0; y < height; ++y) {
    segments.push_back({y, 0, width});
    for (size_t length = 1; length < std::min(width, size_t(50)); ++length) segments.push_back({y, 0, length});
    for (size_t end = 33; end <= std::min(width, size_t(81)); end += 3) segments.push_back({y, 32, end});
  }
  constexpr float kUntouched = -7.0f;
  const auto run = [&](const Segment& s, std::vector<float>& rgb, bool simd) {
    rgb.assign(3 * width, kUntouched);
    const auto kernel = simd ? SsrConeRowSimd : SsrConeRowScalar;
    return kernel(context, gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(s.y), trace.hitX.ConstRow(s.y),
                  trace.hitY.ConstRow(s.y), trace.confidence.ConstRow(s.y), s.y, s.begin, s.end, rgb.data(),
                  rgb.data() + width, rgb.data() + 2 * width);
  };
  std::vector<std::vector<float>> expected(segments.size());
  std::vector<SsrConeCounts> expectedCounts(segments.size());
  for (size_t i = 0; i < segments.size(); ++i) expectedCounts[i] = run(segments[i], expected[i], false);
  std::vector<float> actual;
  const size_t targets = test::ForEachSimdTarget([&](const char* target) {
    for (size_t i = 0; i < segments.size(); ++i) {
      const SsrConeCounts counts = run(segments[i], actual, true);
      CAPTURE(target, segments[i].y, segments[i].begin, segments[i].end, maxSamples);
      REQUIRE(test::FirstDifferentBits(actual.data(), expected[i].data(), actual.size()) == actual.size());
      REQUIRE(counts.samples == expectedCounts[i].samples);
      REQUIRE(counts.pixels == expectedCounts[i].pixels);
    }
  });
  CHECK(targets >= 2);
}

TEST_CASE("Cone trace: the SIMD row kernel equals the scalar one on every target", "[cone][simd]") {
  SECTION("step image, hits straight up, uniform and mixed roughness") {
    const ColorPyramid pyramid = StepPyramid();
    const SsrTraceOutputs trace = VerticalHits(0.37f);
    for (const uint32_t code : {0u, 1u, 64u, 200u, 255u}) {
      CheckConeRowTwins(UniformRoughness(kStepWidth, kStepHeight, code), pyramid, trace, SsrConeParams{}.maxSamples);
    }
    // Every code, neighbours differing: each vector's circles read several levels.
    GBuffer mixed = MakeGBuffer(int(kStepWidth), int(kStepHeight), NormalEncoding::kOct24);
    for (size_t y = 0; y < kStepHeight; ++y) {
      for (size_t x = 0; x < kStepWidth; ++x)
        mixed.word[GBufferWord::kNormalRoughness].MutableRow(y)[x] = uint32_t((x * 7 + y * 13) & 255) << 24;
    }
    for (const int maxSamples : {1, 7, 64}) CheckConeRowTwins(mixed, pyramid, trace, maxSamples);
  }
  SECTION("random images: hits at the pixel itself, the corners and anywhere; some without a hit") {
    std::mt19937 rng(11);
    for (const auto& [width, height] : kOddSizes) {
      const ColorPyramid pyramid = RandomPyramid(width, height, rng);
      const std::vector<std::pair<float, float>> corners = Corners(width, height);
      const float w = float(width), h = float(height);
      std::uniform_real_distribution<float> hitX(0.0f, std::nextafter(w, 0.0f)), hitY(0.0f, std::nextafter(h, 0.0f));
      std::uniform_int_distribution<uint32_t> code(0, 255);
      std::uniform_int_distribution<int> pattern(0, 6);
      GBuffer gbuffer = MakeGBuffer(int(width), int(height), NormalEncoding::kOct24);
      SsrTraceOutputs trace{MakePlane<float>(width, height, -1.0f), MakePlane<float>(width, height, -1.0f),
                            MakePlane<float>(width, height, 0.0f), {}};
      for (size_t y = 0; y < height; ++y) {
        for (size_t x = 0; x < width; ++x) {
          gbuffer.word[GBufferWord::kNormalRoughness].MutableRow(y)[x] = code(rng) << 24;
          const int p = pattern(rng);
          if (p == 6) continue;  // no hit
          std::pair<float, float> hit{float(x) + 0.5f, float(y) + 0.5f};
          if (p >= 1 && p <= 4) hit = corners[size_t(p - 1)];
          if (p == 5) hit = {hitX(rng), hitY(rng)};
          trace.hitX.MutableRow(y)[x] = hit.first;
          trace.hitY.MutableRow(y)[x] = hit.second;
          trace.confidence.MutableRow(y)[x] = 0.5f;
        }
      }
      for (const int maxSamples : {1, 7, 64}) CheckConeRowTwins(gbuffer, pyramid, trace, maxSamples);
    }
  }
}

TEST_CASE("Cone trace: the SIMD pass gives the scalar pass's bytes on every target, default scene", "[cone][simd]") {
  test::ForEachDefaultSceneFrame([](const Frame& frame) {
    CAPTURE(frame.view.width, frame.view.height);
    REQUIRE(frame.reflections);
    const SsrConeInputs in{frame.gbuffer.gbuffer, frame.colorPyramid, frame.ssrTrace.hitX, frame.ssrTrace.hitY,
                           frame.ssrTrace.confidence};
    SsrConeOutputs expected;
    const SsrConeStats expectedStats = RunSsrCone(in, {}, expected, KernelPath::kScalar);
    if (frame.view.width > 1) CHECK(expectedStats.pixels > size_t(frame.view.width));
    const size_t targets = test::ForEachSimdTarget([&](const char* target) {
      CAPTURE(target);
      SsrConeOutputs actual;
      const SsrConeStats stats = RunSsrCone(in, {}, actual, KernelPath::kSimd);
      for (int c = 0; c < 3; ++c) CHECK(test::SameBytes(actual.reflected.c[c], expected.reflected.c[c]));
      CHECK(stats.samples == expectedStats.samples);
      CHECK(stats.pixels == expectedStats.pixels);
    });
    CHECK(targets >= 2);
  });
}

}  // namespace
}  // namespace ssgi
