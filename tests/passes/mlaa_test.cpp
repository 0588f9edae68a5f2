// The morphological anti-aliasing (passes/mlaa.h): its luma and edge twins, its run weights, what it
// does to a stair-step edge, a flat image and a gradient, and its determinism within the frame.
#include "passes/mlaa.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "core/parallel.h"
#include "passes/antialias.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

bool SamePlanes(const MlaaOutputs& a, const MlaaOutputs& b) {
  return test::SameBytes(a.luma, b.luma) && test::SameBytes(a.edges, b.edges) &&
         test::SameBytes(a.weights, b.weights) && test::SameBytes(a.coverage, b.coverage);
}

// The image after the morphological pass and the blend, as the frame runs them.
Plane3<float> Antialiased(const Plane3<float>& image, MlaaOutputs& mlaa) {
  RunMlaa({image}, {}, mlaa);
  Plane3<float> out;
  RunAntialias({mlaa.coverage, image}, out);
  return out;
}

Plane3<float> Grey(size_t width, size_t height, const std::function<float(size_t x, size_t y)>& value) {
  Plane3<float> image = MakePlane3<float>(width, height, 0.0f);
  for (size_t y = 0; y < height; ++y)
    for (size_t x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) image.c[c].MutableRow(y)[x] = value(x, y);
  return image;
}

TEST_CASE("mlaa: the luma, edge and coverage row twins equal their scalar definitions on every target",
          "[mlaa][simd]") {
  std::mt19937 rng(5);
  const std::vector<float> special = test::SpecialFloats();
  std::uniform_real_distribution<float> radiance(0.0f, 8.0f), luma(0.0f, 1.0f);
  for (size_t width = 1; width <= 67; ++width) {
    CAPTURE(width);
    std::vector<float> rgb[3];
    for (std::vector<float>& channel : rgb) {
      channel.resize(width);
      for (float& v : channel) v = rng() % 5 == 0 ? special[rng() % special.size()] : radiance(rng);
    }
    const float* const in[3] = {rgb[0].data(), rgb[1].data(), rgb[2].data()};
    CHECK(test::FirstDifferenceOfTwins(width, MlaaLumaRowScalar, MlaaLumaRowSimd, in, width, 1.5f) == width + 1);
    // Luma rows with ties and steps of every size around the threshold.
    std::vector<float> rows[4];
    for (std::vector<float>& row : rows) {
      row.resize(width);
      for (float& v : row) v = rng() % 4 == 0 ? 0.5f : (rng() % 3 == 0 ? 0.5f + 0.1f * float(rng() % 3) : luma(rng));
    }
    const float* const lumaRows[4] = {rows[0].data(), rows[1].data(), rows[2].data(), rows[3].data()};
    std::vector<uint32_t> scalar(width + 1, 7u);
    MlaaEdgeRowScalar(lumaRows, width, 0.1f, scalar.data());
    test::ForEachSimdTarget([&](const char* target) {
      std::vector<uint32_t> simd(width + 1, 7u);
      MlaaEdgeRowSimd(lumaRows, width, 0.1f, simd.data());
      CAPTURE(target);
      CHECK(simd == scalar);
    });
    // Weights with shares of every size, ties between the axes among them.
    std::vector<uint32_t> weights(width), below(width);
    const auto randomWeights = [&] {
      const uint32_t kind = rng() % 3;
      return kind == 0 ? 0u : kind == 1 ? rng() & 0xFFFFFFFFu : (rng() & 0x80808080u) >> (rng() % 2);
    };
    for (uint32_t& w : weights) w = randomWeights();
    for (uint32_t& w : below) w = randomWeights();
    std::vector<uint32_t> scalarCoverage(width + 1, 7u);
    const size_t scalarCount = MlaaCoverageRowScalar(weights.data(), below.data(), width, scalarCoverage.data());
    test::ForEachSimdTarget([&](const char* target) {
      std::vector<uint32_t> simd(width + 1, 7u);
      CAPTURE(target);
      CHECK(MlaaCoverageRowSimd(weights.data(), below.data(), width, simd.data()) == scalarCount);
      CHECK(simd == scalarCoverage);
    });
  }
}

TEST_CASE("mlaa: a run's weights are the areas between its silhouette and the edge", "[mlaa]") {
  uint32_t codes[2];
  // One pixel between a crossing below at its start and above at its end (a Z): the line from -1/2 to
  // +1/2 cuts a triangle of 1/8 off each side.
  MlaaRunWeights(1, 0, -1, 1, codes);
  CHECK(codes[0] == 32);
  CHECK(codes[1] == 32);
  // An L of two pixels: the line from +1/2 at the start to 0 at the middle covers 1/4 of the first
  // pixel, nothing of the second.
  MlaaRunWeights(2, 0, 1, 0, codes);
  CHECK((codes[0] == 64 && codes[1] == 0));
  MlaaRunWeights(2, 1, 1, 0, codes);
  CHECK((codes[0] == 0 && codes[1] == 0));
  // A Z of n pixels is the straight line from -1/2 to +1/2: n/8 on each side in all, each pixel's
  // area that of the line over it.
  for (uint32_t n : {3u, 4u, 7u, 16u, 101u}) {
    double first = 0.0, second = 0.0;
    for (uint32_t k = 0; k < n; ++k) {
      MlaaRunWeights(n, k, -1, 1, codes);
      const double u0 = k;
      const auto line = [&](double u) { return u / n - 0.5; };
      // The exact areas of the line's parts above (> 0) and below 0 over [u0, u1].
      double above = 0.0, below = 0.0;
      constexpr int kSteps = 4096;
      for (int i = 0; i < kSteps; ++i) {
        const double v = line(u0 + (i + 0.5) / kSteps);
        (v > 0 ? above : below) += std::abs(v) / kSteps;
      }
      CAPTURE(n, k);
      CHECK(std::abs(codes[0] / 256.0 - above) <= 0.5 / 256 + 1e-6);
      CHECK(std::abs(codes[1] / 256.0 - below) <= 0.5 / 256 + 1e-6);
      first += codes[0];
      second += codes[1];
    }
    CHECK(first / 256.0 == Approx(n / 8.0).margin(n / 512.0));
    CHECK(second / 256.0 == Approx(n / 8.0).margin(n / 512.0));
  }
}

// A white half-plane under a straight line on black, sampled at pixel centres (`steep`: the line
// runs down the image, else across it): after the pass each pixel the line crosses is near the share
// of it the half-plane covers.
void CheckStairStep(bool steep, double slope) {
  constexpr size_t kWidth = 96, kHeight = 64;
  const auto below = [&](double x, double y) {
    return steep ? x > 40.0 + slope * (y - 32.0) : y > 30.0 + slope * (x - 48.0);
  };
  const Plane3<float> aliased =
      Grey(kWidth, kHeight, [&](size_t x, size_t y) { return below(x + 0.5, y + 0.5) ? 1.0f : 0.0f; });
  MlaaOutputs mlaa;
  const Plane3<float> blended = Antialiased(aliased, mlaa);
  double offSum = 0.0, blendedSum = 0.0, worst = 0.0;
  size_t compared = 0;
  for (size_t y = 4; y + 4 < kHeight; ++y)
    for (size_t x = 4; x + 4 < kWidth; ++x) {
      constexpr int kGrid = 64;
      int covered = 0;
      for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) covered += below(x + (i + 0.5) / kGrid, y + (j + 0.5) / kGrid);
      const double exact = double(covered) / (kGrid * kGrid);
      if (exact == 0.0 || exact == 1.0) continue;
      ++compared;
      const double off = aliased.c[0].ConstRow(y)[x] - exact, after = blended.c[0].ConstRow(y)[x] - exact;
      offSum += off * off;
      blendedSum += after * after;
      worst = std::max(worst, std::abs(after));
    }
  const double offRmse = std::sqrt(offSum / compared), blendedRmse = std::sqrt(blendedSum / compared);
  CAPTURE(steep, slope, compared, offRmse, blendedRmse, worst);
  CHECK(compared > 50);
  CHECK(offRmse > 0.25);
  CHECK(blendedRmse < 0.25 * offRmse);
  CHECK(worst < 0.15);
}

// At slope 1/8 every run is 8 pixels long and its silhouette is the line itself: the blend is exact.
TEST_CASE("mlaa: a stair-step edge is blended toward each pixel's covered share", "[mlaa]") {
  for (double slope : {0.125, 0.23, 0.4}) {
    CheckStairStep(false, slope);
    CheckStairStep(true, -slope);
  }
}

TEST_CASE("mlaa: a flat image and a smooth gradient keep their bytes, and HDR stays finite", "[mlaa]") {
  for (const auto& value : std::vector<std::function<float(size_t, size_t)>>{
           [](size_t, size_t) { return 0.5f; },
           [](size_t x, size_t y) { return 0.2f + 0.03f * float(x) + 0.01f * float(y); }}) {
    const Plane3<float> image = Grey(67, 45, value);
    MlaaOutputs mlaa;
    const Plane3<float> out = Antialiased(image, mlaa);
    const MlaaStats stats = RunMlaa({image}, {}, mlaa);
    CHECK(stats.edgePixels == 0);
    CHECK(stats.blendPixels == 0);
    CHECK(test::SameBytes(out, image));
  }
  // Blocks of the largest radiance, zero and denormals, with a slanted border.
  const Plane3<float> hdr = Grey(80, 60, [](size_t x, size_t y) {
    if (y * 3 > x + 20) return 65504.0f;
    return (x / 7 + y / 5) % 2 ? 1e-40f : 0.0f;
  });
  MlaaOutputs mlaa;
  const Plane3<float> out = Antialiased(hdr, mlaa);
  size_t blended = 0;
  for (size_t y = 0; y < 60; ++y)
    for (size_t x = 0; x < 80; ++x) {
      const float v = out.c[0].ConstRow(y)[x];
      CHECK((std::isfinite(v) && v >= 0.0f && v <= 65504.0f));
      blended += v != hdr.c[0].ConstRow(y)[x];
    }
  CHECK(blended > 20);
}

TEST_CASE("mlaa: the same bytes on the default scene at any thread count and on any kernel path", "[mlaa][simd]") {
  const test::DefaultScene defaults = test::LoadDefaultScene();
  for (const auto& [width, height] : {std::pair{331, 197}, std::pair{67, 45}, std::pair{1, 1}}) {
    CAPTURE(width, height);
    FrameConfig config = defaults.config;
    config.width = width;
    config.height = height;
    config.antialiasing = Antialiasing::kMlaa;
    config.shadowMap.resolution = 512;
    const Frame frame = RenderFrame(defaults.scene, config);
    REQUIRE(frame.antialias);
    REQUIRE(frame.stats.mlaa);
    if (width > 1) CHECK(frame.stats.mlaa->blendPixels > 0);
    MlaaOutputs reference;
    RunMlaa({frame.Composed()}, {}, reference, KernelPath::kScalar);
    CHECK(SamePlanes(frame.mlaa, reference));
    Plane3<float> blended;
    RunAntialias({reference.coverage, frame.Composed()}, blended, KernelPath::kScalar);
    CHECK(test::SameBytes(frame.Result(), blended));
    for (int threads : {1, 2, 3}) {
      const ThreadLimit limit(threads);
      MlaaOutputs out;
      RunMlaa({frame.Composed()}, {}, out);
      CHECK(SamePlanes(out, reference));
    }
    CHECK(test::TargetsWhereKernelPathsDiffer(
              [&](KernelPath kernels) {
                MlaaOutputs out;
                RunMlaa({frame.Composed()}, {}, out, kernels);
                return out;
              },
              SamePlanes) == "");
  }
}

TEST_CASE("mlaa: planned, and off or another image changes what it should", "[mlaa][frame]") {
  const test::DefaultScene defaults = test::LoadDefaultScene();
  FrameConfig config = defaults.config;
  config.width = 96;
  config.height = 64;
  config.shadowMap.resolution = 256;
  config.antialiasing = Antialiasing::kOff;
  const Frame off = RenderFrame(defaults.scene, config);
  config.antialiasing = Antialiasing::kMlaa;
  const Frame mlaa = RenderFrame(defaults.scene, config);
  CHECK(mlaa.antialias);
  CHECK(mlaa.plan.antialias.why == "mlaa searches the image's luma edges (pixels have geometry)");
  CHECK(mlaa.gbuffer.edgeCoverage.xsize() == 0);
  CHECK(mlaa.stats.antialias->edgePixels == mlaa.stats.mlaa->blendPixels);
  CHECK(test::SameBytes(off.Result(), mlaa.Composed()));
  CHECK_FALSE(test::SameBytes(off.Result(), mlaa.Result()));
  // A camera that sees only the constant background: no edge, no pass.
  config.environment = ConstantEnvironment(glm::vec3(0.25f));
  const Frame none = RenderFrame(test::FacingTheSky(defaults.scene), config);
  CHECK_FALSE(none.antialias);
  CHECK(none.plan.antialias.why == "no pixel has geometry and the environment is one colour");
  CHECK_FALSE(none.stats.mlaa);
  CHECK_FALSE(none.stats.antialias);
}

}  // namespace
}  // namespace ssgi
