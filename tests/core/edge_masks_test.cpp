#include "core/edge_masks.h"

#include <catch2/catch.hpp>
#include <string>
#include <vector>

namespace ssgi {
namespace {

constexpr int kWidth = 16, kHeight = 8;

// A one-channel (visibility) or RGB image of the test's size from value(x, y).
template <typename Value>
FloatImage Image(int channels, const Value& value) {
  FloatImage image;
  image.width = kWidth;
  image.height = kHeight;
  image.channelNames = channels == 1 ? std::vector<std::string>{"Y"} : std::vector<std::string>{"R", "G", "B"};
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < channels; ++c) image.pixels.push_back(value(x, y));
  return image;
}

NeighbourPairs NoPairs() { return {kWidth, kHeight, std::vector<uint8_t>(size_t(kWidth) * kHeight, 0)}; }

// The mask as rows of '#' (in) and '.', so that a failure shows where.
std::vector<std::string> Rows(const std::vector<uint8_t>& mask) {
  std::vector<std::string> rows;
  for (int y = 0; y < kHeight; ++y) {
    std::string row;
    for (int x = 0; x < kWidth; ++x) row += mask[size_t(y) * kWidth + size_t(x)] ? '#' : '.';
    rows.push_back(row);
  }
  return rows;
}

// A plane lit left of the line between columns 4 and 5 and in shadow right of it, then a penumbra
// eight pixels wide back to full light from column 8: the hard edge's two columns and their
// neighbours are marked, the wide penumbra's steps of 1/8 are not.
float HardEdgeThenPenumbra(int x, int) { return x <= 4 ? 1.0f : x <= 7 ? 0.0f : float(x - 7) / 8.0f; }

// A white plane's direct light under `visibility`.
FloatImage LitBy(const FloatImage& visibility) {
  return Image(3, [&](int x, int y) { return visibility.pixels[size_t(y) * kWidth + size_t(x)]; });
}

TEST_CASE("edge masks: a hard shadow edge on one surface marks its pixels and their neighbours", "[edge_masks]") {
  const FloatImage visibility = Image(1, HardEdgeThenPenumbra);
  CHECK(Rows(ShadowEdgeMask(visibility, LitBy(visibility), NoPairs())) ==
        std::vector<std::string>(kHeight, "...####........."));
}

TEST_CASE("edge masks: a step in visibility where the light is already dark is no shadow edge", "[edge_masks]") {
  // A sphere's terminator: the visibility drops from 1 to 0 where the surface turns from the light,
  // whose light there is a hundredth of full light.
  const FloatImage visibility = Image(1, [](int x, int) { return x <= 4 ? 1.0f : 0.0f; });
  const FloatImage grazing = Image(3, [](int x, int) { return x <= 4 ? 0.01f : 0.0f; });
  CHECK(Rows(ShadowEdgeMask(visibility, grazing, NoPairs())) == std::vector<std::string>(kHeight, "................"));
}

TEST_CASE("edge masks: a shadow edge along a geometric edge belongs to the geometric edge", "[edge_masks]") {
  // The caster's silhouette between columns 4 and 5 (its shadow meets it there) and another
  // geometric edge between columns 11 and 12.
  NeighbourPairs geometric = NoPairs();
  for (int y = 0; y < kHeight; ++y) {
    geometric.bits[size_t(y) * kWidth + 4] |= kPairRight;
    geometric.bits[size_t(y) * kWidth + 11] |= kPairRight;
  }
  const FloatImage visibility = Image(1, HardEdgeThenPenumbra);
  CHECK(Rows(ShadowEdgeMask(visibility, LitBy(visibility), geometric)) ==
        std::vector<std::string>(kHeight, "................"));
  CHECK(Rows(PairMask(geometric)) == std::vector<std::string>(kHeight, "...####...####.."));

  // The shadow edge one pixel further right: its pairs are on one surface, but all its pixels but one
  // column lie within the geometric edge's dilation.
  const FloatImage shifted = Image(1, [](int x, int) { return x <= 5 ? 1.0f : 0.0f; });
  CHECK(Rows(ShadowEdgeMask(shifted, LitBy(shifted), geometric)) ==
        std::vector<std::string>(kHeight, ".......#........"));
}

TEST_CASE("edge masks: a horizontal shadow edge marks the rows beside it", "[edge_masks]") {
  const FloatImage visibility = Image(1, [](int, int y) { return y <= 2 ? 0.0f : 1.0f; });
  const std::vector<std::string> expected = {"................", "################", "################",
                                             "################", "################", "................",
                                             "................", "................"};
  CHECK(Rows(ShadowEdgeMask(visibility, LitBy(visibility), NoPairs())) == expected);
}

TEST_CASE("edge masks: a step in the reflected light on a reflective surface is a reflection edge", "[edge_masks]") {
  // Rows 0-3: the reflection of a bright object ends between columns 4 and 5. Rows 4-7: the same step
  // in the direct light (a shadow), under a constant reflection: not a reflection edge.
  const FloatImage direct = Image(3, [](int x, int y) { return y >= 4 && x <= 4 ? 1.0f : 0.5f; });
  const FloatImage indirect = Image(3, [](int x, int y) { return y <= 3 && x <= 4 ? 0.5f : 0.0f; });
  std::vector<uint8_t> reflective(size_t(kWidth) * kHeight, 1);
  const std::vector<std::string> expected = {"...####.........", "...####.........", "...####.........",
                                             "...####.........", "...####.........", "................",
                                             "................", "................"};
  CHECK(Rows(ReflectionEdgeMask(direct, indirect, reflective, NoPairs())) == expected);

  // The same step on a rough surface, which the trace does not reflect.
  std::fill(reflective.begin(), reflective.end(), uint8_t(0));
  CHECK(Rows(ReflectionEdgeMask(direct, indirect, reflective, NoPairs())) ==
        std::vector<std::string>(kHeight, "................"));

  // A step too small to see: 0.01 of reflected light on 0.5 of direct.
  std::fill(reflective.begin(), reflective.end(), uint8_t(1));
  const FloatImage faint = Image(3, [](int x, int) { return x <= 4 ? 0.01f : 0.0f; });
  CHECK(Rows(ReflectionEdgeMask(Image(3, [](int, int) { return 0.5f; }), faint, reflective, NoPairs())) ==
        std::vector<std::string>(kHeight, "................"));
}

}  // namespace
}  // namespace ssgi
