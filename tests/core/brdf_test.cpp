#include "core/brdf.h"

#include <cstring>

#include <catch2/catch.hpp>

namespace ssgi {
namespace {

TEST_CASE("DFG table: energy bounded, mirror at normal incidence, deterministic", "[brdf]") {
  const DfgTable table = BuildDfgTable();
  for (const glm::vec2& ab : table.ab) {
    CHECK(ab.x >= 0.0f);
    CHECK(ab.y >= 0.0f);
    CHECK(ab.x + ab.y <= 1.0f);
  }
  const glm::vec2 mirror = table.ab[kDfgSize - 1];  // roughness 0, n.v = 1
  CHECK(mirror.x == Approx(1.0f).margin(0.02));
  CHECK(mirror.y == Approx(0.0f).margin(0.02));
  const glm::vec3 weight = SpecularWeight(glm::vec3(0.04f, 0.5f, 1.0f), 1.0f, 0.0f);
  CHECK(weight.x == Approx(0.04f).margin(0.02));
  CHECK(weight.z == Approx(1.0f).margin(0.02));
  // Grazing, rough: Fresnel raises B, roughness lowers the total.
  CHECK(table.ab[(kDfgSize - 1) * kDfgSize + 2].y > table.ab[(kDfgSize - 1) * kDfgSize + kDfgSize - 1].y);
  const DfgTable again = BuildDfgTable();
  CHECK(std::memcmp(table.ab.data(), again.ab.data(), sizeof(table.ab)) == 0);
}

}  // namespace
}  // namespace ssgi
