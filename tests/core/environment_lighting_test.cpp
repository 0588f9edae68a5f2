// The environment as the passes read it (core/environment_lighting.h): the octahedral map and its
// seams, and a constant environment read exactly.
#include "core/environment_lighting.h"

#include <catch2/catch.hpp>
#include <random>

namespace ssgi {
namespace {

TEST_CASE("octahedral map: decode inverts encode over the sphere, the sky inside the diamond", "[environment]") {
  std::mt19937 rng(7);
  std::normal_distribution<float> gauss;
  for (int i = 0; i < 20000; ++i) {
    glm::vec3 d(gauss(rng), gauss(rng), gauss(rng));
    if (glm::length(d) < 1e-3f) continue;
    d = glm::normalize(d);
    const glm::vec2 uv = OctahedralEncode(d);
    CAPTURE(d.x, d.y, d.z, uv.x, uv.y);
    CHECK(uv.x >= 0.0f);
    CHECK(uv.x <= 1.0f);
    CHECK(uv.y >= 0.0f);
    CHECK(uv.y <= 1.0f);
    CHECK(glm::dot(OctahedralDecode(uv), d) > 0.99999f);
    // The sky (y >= 0) is the inner diamond |u - 0.5| + |v - 0.5| <= 0.5.
    CHECK((std::abs(uv.x - 0.5f) + std::abs(uv.y - 0.5f) <= 0.5f + 1e-6f) == (d.y >= -1e-6f || d.y >= 0.0f));
  }
  CHECK(OctahedralDecode({0.5f, 0.5f}).y == Approx(1.0f));
  CHECK(OctahedralDecode({0.0f, 0.0f}).y == Approx(-1.0f));
}

TEST_CASE("octahedral map: just outside an edge continues across the seam", "[environment]") {
  // A point mirrored about an edge's midpoint decodes to a direction close to the point just inside:
  // the rule the levels' borders copy (texel (-1, j) holds texel (0, size - 1 - j)).
  for (float v : {0.1f, 0.3f, 0.5f, 0.77f}) {
    const float e = 1e-3f;
    const glm::vec3 inside = OctahedralDecode({e, v});
    const glm::vec3 across = OctahedralDecode({e, 1.0f - v});
    CAPTURE(v);
    CHECK(glm::dot(inside, across) > 0.999f);
    const glm::vec3 inside2 = OctahedralDecode({v, 1.0f - e});
    const glm::vec3 across2 = OctahedralDecode({1.0f - v, 1.0f - e});
    CHECK(glm::dot(inside2, across2) > 0.999f);
  }
}

TEST_CASE("environment lighting: a constant environment reads its radiance exactly", "[environment]") {
  const Environment constant = ConstantEnvironment({0.05f, 0.06f, 0.08f});
  const EnvironmentLighting lighting = PrepareEnvironmentLighting(constant);
  CHECK(lighting.constant);
  for (const glm::vec3 d : {glm::vec3(0, 1, 0), glm::normalize(glm::vec3(1, -2, 3))}) {
    CHECK(EnvironmentRadiance(lighting, d) == constant.radiance);
    CHECK(PrefilteredEnvironment(lighting, d, 0.37f) == constant.radiance);
    CHECK(EnvironmentIrradiance(lighting, d) == constant.radiance);
  }
  CHECK(SameEnvironment(lighting, constant));
  CHECK_FALSE(SameEnvironment(lighting, ConstantEnvironment({1.0f, 0.0f, 0.0f})));
}

}  // namespace
}  // namespace ssgi
