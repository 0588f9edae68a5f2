// Environments (core/environment.h): the analytic sky, HDR images and their sampling, and their
// tables for the passes (core/environment_lighting.h).
#include "core/environment.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "core/brdf.h"
#include "core/environment_lighting.h"
#include "core/image_io.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

glm::vec3 UniformDirection(std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const float z = 1.0f - 2.0f * unit(rng), phi = 2.0f * kPi * unit(rng);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return {r * std::cos(phi), z, r * std::sin(phi)};
}

// A map of `width` x `height` texels of value 0.1 but one bright texel.
std::shared_ptr<EnvironmentMap> MapWithHotTexel(int width, int height, int hotI, int hotJ, float rotationTurns = 0.0f) {
  std::vector<glm::vec3> texels(size_t(width) * size_t(height), glm::vec3(0.1f));
  texels[size_t(hotJ) * size_t(width) + size_t(hotI)] = glm::vec3(500.0f);
  return std::make_shared<EnvironmentMap>(width, height, std::move(texels), rotationTurns);
}

TEST_CASE("environment: a map's density integrates to one and is the density it samples", "[environment]") {
  const auto map = MapWithHotTexel(64, 32, 40, 9, 0.3f);
  std::mt19937 rng(3);
  double mean = 0.0;
  constexpr int kDirections = 200000;
  for (int i = 0; i < kDirections; ++i) mean += map->Pdf(UniformDirection(rng));
  CHECK(mean / kDirections * 4.0 * kPi == Approx(1.0).epsilon(0.02));
  // Samples carry their own density and land in the hot texel about as often as its weight says.
  std::uniform_real_distribution<float> unit(0.0f, 0.99999994f);
  size_t hot = 0;
  const glm::vec3 hotRadiance(500.0f);
  for (int i = 0; i < 20000; ++i) {
    const EnvironmentSample s = map->Sample(unit(rng), unit(rng));
    CHECK(std::abs(glm::length(s.direction) - 1.0f) < 1e-4f);
    CHECK(s.pdf == Approx(map->Pdf(s.direction)).epsilon(1e-3));
    CHECK(s.radiance == map->Radiance(s.direction));
    hot += s.radiance == hotRadiance ? 1 : 0;
  }
  CHECK(hot > 20000 * 0.5);
}

TEST_CASE("environment: the analytic sky runs from the horizon to the zenith and glows around the sun",
          "[environment]") {
  SkyParams sky;
  sky.sunGlow = glm::vec3(2.0f);
  sky.sunDirection = glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f));
  CHECK(SkyRadiance(sky, {0.0f, 1.0f, 0.0f}) == sky.zenith + sky.sunGlow * std::pow(std::sqrt(0.5f), 16.0f));
  CHECK(glm::length(SkyRadiance(sky, {0.0f, 0.0f, 1.0f}) - sky.horizon) < 1e-6f);
  CHECK(glm::length(SkyRadiance(sky, {0.0f, -1.0f, 0.0f}) - sky.ground) < 1e-6f);
  CHECK(glm::length(SkyRadiance(sky, sky.sunDirection) - (SkyRadiance(sky, sky.sunDirection) - sky.sunGlow)) ==
        Approx(glm::length(sky.sunGlow)));
  const Environment environment = MakeSkyEnvironment(sky);
  CHECK(environment.kind == EnvironmentKind::kSky);
  CHECK(!environment.IsBlack());
  // The map holds the sky: near the zenith and the horizon it reads what the sky gives.
  for (const glm::vec3 d : {glm::vec3(0.0f, 0.999f, 0.0447f), glm::normalize(glm::vec3(0.3f, 0.01f, 1.0f))})
    CHECK(glm::length(environment.Radiance(d) - SkyRadiance(sky, d)) < 0.02f);
}

TEST_CASE("environment: an HDR image is read with its rotation and intensity, and bad ones are refused",
          "[environment]") {
  test::ScratchDir dir("environment-image");
  // 8 x 4, all 1 but one texel at u in [0.5, 0.625), the row at the horizon: 9.
  std::vector<float> rgb(8 * 4 * 3, 1.0f);
  for (int c = 0; c < 3; ++c) rgb[(2 * 8 + 4) * 3 + c] = 9.0f;
  std::vector<float> planes[3];
  for (int c = 0; c < 3; ++c)
    for (size_t p = 0; p < 32; ++p) planes[c].push_back(rgb[p * 3 + size_t(c)]);
  WriteExr(dir / "sky.exr", 8, 4,
           {{"R", false, planes[0].data(), 8}, {"G", false, planes[1].data(), 8}, {"B", false, planes[2].data(), 8}});
  const Environment plain = LoadImageEnvironment(dir / "sky.exr", 0.0f, 2.0f);
  // u = 0.5 + atan2(x, -z) / 2 pi: looking along -z is u = 0.5, just below the horizon is row 2.
  const glm::vec3 ahead = glm::normalize(glm::vec3(0.05f, -0.1f, -1.0f));
  CHECK(plain.Radiance(ahead) == glm::vec3(18.0f));
  CHECK(plain.Radiance({0.0f, 1.0f, 0.0f}) == glm::vec3(2.0f));
  // A quarter turn moves the bright texel a quarter of the way round.
  const Environment turned = LoadImageEnvironment(dir / "sky.exr", 90.0f, 2.0f);
  CHECK(turned.Radiance(ahead) == glm::vec3(2.0f));
  CHECK(!turned.Same(plain));
  for (int c = 0; c < 3; ++c) planes[c][5] = -1.0f;
  WriteExr(dir / "bad.exr", 8, 4,
           {{"R", false, planes[0].data(), 8}, {"G", false, planes[1].data(), 8}, {"B", false, planes[2].data(), 8}});
  CHECK_THROWS_WITH(LoadImageEnvironment(dir / "bad.exr", 0.0f, 1.0f),
                    Catch::Contains("bad.exr: pixel (5, 0) is negative"));
}

TEST_CASE("environment lighting: a sky's tables read its radiance and its irradiance", "[environment]") {
  SkyParams sky;
  const Environment environment = MakeSkyEnvironment(sky);
  const EnvironmentLighting lighting = PrepareEnvironmentLighting(environment);
  CHECK_FALSE(lighting.constant);
  std::mt19937 rng(11);
  for (int i = 0; i < 500; ++i) {
    const glm::vec3 d = UniformDirection(rng);
    CAPTURE(d.x, d.y, d.z);
    CHECK(glm::length(EnvironmentRadiance(lighting, d) - SkyRadiance(sky, d)) < 0.05f);
  }
  // The irradiance over pi against a direct quadrature of the sky's radiance times the cosine.
  for (const glm::vec3 n : {glm::vec3(0, 1, 0), glm::vec3(0, -1, 0), glm::normalize(glm::vec3(1, 0.2f, 0.3f))}) {
    glm::dvec3 sum(0.0);
    constexpr int kSamples = 200000;
    for (int i = 0; i < kSamples; ++i) {
      const glm::vec3 d = UniformDirection(rng);
      sum += glm::dvec3(SkyRadiance(sky, d)) * double(std::max(0.0f, glm::dot(n, d)));
    }
    const glm::vec3 expected = glm::vec3(sum / double(kSamples) * 4.0);  // (4 pi / N) sum / pi
    const glm::vec3 irradiance = EnvironmentIrradiance(lighting, n);
    CAPTURE(n.x, n.y, n.z, expected.x, irradiance.x, expected.z, irradiance.z);
    // Nine SH coefficients represent a smooth sky's irradiance within a few percent.
    CHECK(glm::length(irradiance - expected) < 0.04f * glm::length(expected) + 0.01f);
  }
  // A rough prefiltered read is a blur of the sky: between the zenith and the horizon looking up.
  const glm::vec3 up = PrefilteredEnvironment(lighting, {0.0f, 1.0f, 0.0f}, 1.0f);
  CHECK(up.z < sky.zenith.z + 1e-3f);
  CHECK(up.z > sky.horizon.z * 0.5f);
  CHECK(SameEnvironment(lighting, environment));
}

}  // namespace
}  // namespace ssgi
