#include "core/image_compare.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>

#include "core/error.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

FloatImage Constant(int width, int height, float value, std::vector<std::string> channels = {"R", "G", "B"}) {
  FloatImage image;
  image.width = width;
  image.height = height;
  image.channelNames = std::move(channels);
  image.pixels.assign(size_t(width) * size_t(height) * image.Channels(), value);
  return image;
}

TEST_CASE("compare: identical images", "[compare]") {
  const FloatImage a = Constant(16, 12, 0.5f);
  const ImageDifference d = CompareImages(a, a);
  CHECK(d.rmse == 0.0);
  CHECK(std::isinf(d.psnr));
  CHECK(d.maxError == 0.0);
  CHECK(d.ssim == Approx(1.0).epsilon(1e-12));
}

TEST_CASE("compare: known differences give known metrics", "[compare]") {
  const FloatImage reference = Constant(16, 12, 1.0f);
  FloatImage offset = Constant(16, 12, 1.1f);
  ImageDifference d = CompareImages(offset, reference);
  CHECK(d.rmse == Approx(0.1).epsilon(1e-5));
  CHECK(d.peak == 1.0);
  CHECK(d.psnr == Approx(20.0).epsilon(1e-4));  // 10 log10(1 / 0.01)
  CHECK(d.maxError == Approx(0.1).epsilon(1e-5));
  CHECK(d.rmseDisplay == Approx(1.1 / 2.1 - 0.5).epsilon(1e-5));

  FloatImage spot = reference;
  spot.pixels[(2 * 16 + 3) * 3 + 1] = 1.5f;  // pixel (3, 2), green
  d = CompareImages(spot, reference);
  CHECK(d.maxError == Approx(0.5).epsilon(1e-6));
  CHECK(d.maxX == 3);
  CHECK(d.maxY == 2);
  CHECK(d.rmse == Approx(std::sqrt(0.25 / (16.0 * 12.0 * 3.0))).epsilon(1e-5));

  // Structure matters to SSIM more than a small uniform shift.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> noise(-0.5f, 0.5f);
  FloatImage noisy = reference;
  for (float& v : noisy.pixels) v += noise(rng);
  const double ssimNoisy = CompareImages(noisy, reference).ssim;
  const double ssimOffset = CompareImages(offset, reference).ssim;
  CHECK(ssimNoisy < 0.9);
  CHECK(ssimOffset > ssimNoisy);
  CHECK(ssimOffset < 1.0);

  FloatImage broken = reference;
  broken.pixels[0] = std::nanf("");
  broken.pixels[5] = std::numeric_limits<float>::infinity();
  d = CompareImages(broken, reference);
  CHECK(d.nonFinite == 2);
  CHECK(d.rmse == 0.0);
}

TEST_CASE("compare: layers pick named channels and missing ones are an error", "[compare]") {
  FloatImage dump = Constant(4, 4, 0.0f, {"direct.R", "direct.G", "direct.B", "shadow.visibility"});
  for (size_t i = 0; i < 16; ++i) dump.pixels[i * 4 + 3] = 0.25f;
  const FloatImage visibility = SelectLayer(dump, "shadow.visibility", "dump.exr");
  CHECK(visibility.Channels() == 1);
  CHECK(visibility.pixels[7] == 0.25f);
  CHECK(SelectLayer(dump, "direct", "dump.exr").Channels() == 3);
  const std::string message = test::InputErrorOf([&] { SelectLayer(dump, "indirect", "dump.exr"); });
  CHECK(message.find("dump.exr") != std::string::npos);
  CHECK(message.find("shadow.visibility") != std::string::npos);
  CHECK_FALSE(FindLayer(dump, "indirect"));
  REQUIRE(FindLayer(dump, "shadow.visibility"));
  CHECK(FindLayer(dump, "shadow.visibility")->pixels == visibility.pixels);
}

TEST_CASE("compare: the heat map is black where equal and white at the scale, with its legend below", "[compare]") {
  const FloatImage reference = Constant(40, 1, 0.0f);
  FloatImage test = reference;
  test.pixels[3] = 1.0f;  // pixel 1, red channel
  const Heatmap heat = ErrorHeatmap(test, reference, 1.0);
  REQUIRE(heat.width == 40);
  REQUIRE(heat.height == 1 + kHeatmapLegendRows);
  CHECK(heat.rgb[0] == 0);
  CHECK(heat.rgb[3] == 255);
  CHECK(heat.rgb[4] == 255);
  CHECK(heat.rgb[5] == 255);
  CHECK(heat.scale == 1.0);
  // The legend's colour bar runs from black at the left to white at the right.
  const size_t barRow = size_t(1 + 4) * 40 * 3;
  CHECK(heat.rgb[barRow] == 0);
  CHECK(heat.rgb[barRow + 39 * 3 + 2] == 255);
}

TEST_CASE("compare: the heat map's default scale is the error's 99th percentile, not its outlier", "[compare]") {
  const FloatImage reference = Constant(100, 10, 0.0f);
  FloatImage test = reference;
  for (size_t i = 0; i < 1000; ++i) test.pixels[i * 3] = 0.1f;  // every pixel 0.1 off in red
  test.pixels[0] = 100.0f;                                      // and one outlier
  const Heatmap heat = ErrorHeatmap(test, reference, 0.0);
  CHECK(heat.scale == Approx(0.1));
  CHECK(heat.shareAboveScale == Approx(0.001));
  CHECK(heat.rgb[3] == 255);  // a pixel at the scale is white, not the outlier's 1/1000 of it
}

TEST_CASE("compare: regions from a dump's depth, roughness and visibility, and the error in each", "[compare]") {
  // Four pixels: lit and rough, in shadow and smooth, lit and smooth, background.
  FloatImage dump = Constant(4, 1, 0.0f, {"depth", "roughness", "shadow.visibility"});
  const float depth[] = {1.0f, 2.0f, 3.0f, std::numeric_limits<float>::infinity()};
  const float roughness[] = {0.9f, 0.1f, 0.5f, 0.0f};
  const float visibility[] = {1.0f, 0.2f, 0.5f, 1.0f};
  for (size_t i = 0; i < 4; ++i) {
    dump.pixels[i * 3] = depth[i];
    dump.pixels[i * 3 + 1] = roughness[i];
    dump.pixels[i * 3 + 2] = visibility[i];
  }
  const std::vector<uint8_t> regions = ClassifyRegions(dump, 0.7f, "dump.exr");
  CHECK(regions == std::vector<uint8_t>{kRegionLit, kRegionInShadow | kRegionReflective, kRegionLit | kRegionReflective,
                                        kRegionBackground});
  const FloatImage reference = Constant(4, 1, 1.0f);
  FloatImage test = reference;
  for (int c = 0; c < 3; ++c) test.pixels[size_t(3 + c)] = 0.5f;  // the shadowed pixel half as bright
  const std::vector<RegionDifference> byRegion = CompareRegions(test, reference, regions);
  REQUIRE(byRegion.size() == 4);
  CHECK(byRegion[0].region == kRegionLit);
  CHECK(byRegion[0].pixels == 2);
  CHECK(byRegion[0].rmse == 0.0);
  CHECK(byRegion[0].meanRatio == Approx(1.0));
  CHECK(byRegion[1].region == kRegionInShadow);
  CHECK(byRegion[1].pixels == 1);
  CHECK(byRegion[1].rmse == Approx(0.5));
  CHECK(byRegion[1].meanRatio == Approx(0.5));
  CHECK(byRegion[2].pixels == 2);  // reflective: the shadowed and the lit smooth pixel
  CHECK(byRegion[2].meanRatio == Approx(0.75));
  CHECK(byRegion[3].pixels == 1);
  // Without visibility every covered pixel is lit; without depth there are no regions.
  const FloatImage unshadowed = SelectLayer(dump, "depth", "dump.exr");
  CHECK_THROWS_AS(ClassifyRegions(unshadowed, 0.7f, "dump.exr"), InputError);
}

// A linear ramp upsampled 2x with pixel centres aligned stays the same ramp, sampled at the new
// centres: the resampling the sweep uses for its resolution rows.
TEST_CASE("compare: resizing a ramp to twice its size interpolates it linearly", "[compare]") {
  FloatImage ramp = Constant(8, 6, 0.0f);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x)
      for (int c = 0; c < 3; ++c) ramp.pixels[(size_t(y) * 8 + x) * 3 + c] = float(x) + 10.0f * float(c);
  const FloatImage big = ResizeImage(ramp, 16, 12);
  REQUIRE(big.width == 16);
  REQUIRE(big.height == 12);
  REQUIRE(big.channelNames == ramp.channelNames);
  // Away from the borders (where the filter clamps), new pixel x sits at source x' = (x + 0.5) / 2 - 0.5.
  for (int y = 0; y < 12; ++y)
    for (int x = 2; x < 14; ++x)
      for (int c = 0; c < 3; ++c)
        CHECK(big.pixels[(size_t(y) * 16 + x) * 3 + c] ==
              Approx((float(x) + 0.5f) / 2.0f - 0.5f + 10.0f * float(c)).margin(1e-4));
  const FloatImage same = ResizeImage(Constant(5, 7, 0.25f), 13, 3);
  for (float v : same.pixels) CHECK(v == Approx(0.25f).margin(1e-6));
}

TEST_CASE("compare: box-downsampling averages each block and keeps the channels", "[compare]") {
  FloatImage image = Constant(6, 4, 0.0f, {"Y"});
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) image.pixels[size_t(y) * 6 + x] = float(x + 10 * y);
  const FloatImage small = BoxDownsampled(image, 2);
  REQUIRE(small.width == 3);
  REQUIRE(small.height == 2);
  REQUIRE(small.channelNames == image.channelNames);
  // Block (bx, by) holds x = 2 bx, 2 bx + 1 and y = 2 by, 2 by + 1: its mean is 2 bx + 0.5 + 10 (2 by + 0.5).
  for (int by = 0; by < 2; ++by)
    for (int bx = 0; bx < 3; ++bx)
      CHECK(small.pixels[size_t(by) * 3 + bx] == float(2 * bx + 0.5 + 10 * (2 * by + 0.5)));
}

}  // namespace
}  // namespace ssgi
