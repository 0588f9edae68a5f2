#include "core/pyramid.h"

#include <utility>
#include <vector>

#include <catch2/catch.hpp>

namespace ssgi {
namespace {

TEST_CASE("Pyramid level sizes halve with floor down to 1x1", "[pyramid]") {
  const std::vector<PyramidSize> sizes = PyramidLevelSizes(67, 45);
  const std::vector<std::pair<size_t, size_t>> expected{{67, 45}, {33, 22}, {16, 11}, {8, 5},
                                                        {4, 2},   {2, 1},   {1, 1}};
  REQUIRE(sizes.size() == expected.size());
  for (size_t k = 0; k < sizes.size(); ++k) {
    CHECK(sizes[k].width == expected[k].first);
    CHECK(sizes[k].height == expected[k].second);
  }
  CHECK(PyramidLevelSizes(1, 1).size() == 1);
  CHECK(PyramidLevelSizes(1, 5).size() == 3);  // 1x5 -> 1x2 -> 1x1
}

TEST_CASE("Pyramid paired texels are the leading ones with the footprint 2x, 2x + 1", "[pyramid]") {
  for (size_t source = 1; source <= 100; ++source) {
    const size_t destination = PyramidHalvedSize(source);
    const size_t paired = PyramidPairedTexels(destination, source);
    CAPTURE(source);
    REQUIRE(paired + 1 >= destination);
    for (size_t x = 0; x < destination; ++x)
      CHECK((PyramidFootprintEnd(x, destination, source) == 2 * x + 1) == (x < paired));
  }
}

}  // namespace
}  // namespace ssgi
