#include "passes/composite.h"

#include <cmath>

#include <catch2/catch.hpp>

#include "core/parallel.h"

namespace ssgi {
namespace {

// A hand-made 8x4 G-buffer: smooth metal facing the camera on the left half, background on the right.
struct CompositeFixture {
  ViewProjection view = MakePerspective(CameraDesc{}, 8, 4);
  GBuffer gbuffer = MakeGBuffer(8, 4, NormalEncoding::kOct24);
  Plane3<float> direct = MakePlane3<float>(8, 4, 0.25f);
  Plane3<float> reflected = MakePlane3<float>(8, 4, 2.0f);
  Plane<float> confidence = MakePlane<float>(8, 4, 0.5f);

  CompositeFixture() {
    for (int y = 0; y < 4; ++y) {
      for (int x = 0; x < 4; ++x) {
        gbuffer.word[0].MutableRow(y)[x] = PackAlbedoMetallic(glm::vec3(0.9f, 0.6f, 0.3f), 1.0f);
        gbuffer.word[1].MutableRow(y)[x] = PackNormalRoughness({0.0f, 0.0f, 1.0f}, 0.0f, NormalEncoding::kOct24);
        gbuffer.word[2].MutableRow(y)[x] = PackDepth(3.0f);
      }
    }
    confidence.MutableRow(0)[0] = 0.0f;
  }
  CompositeOutputs Run() const {
    CompositeOutputs out;
    RunComposite({gbuffer, view, direct, reflected, confidence, 0.7f}, out);
    return out;
  }
};

TEST_CASE("composite: result = direct + reflected x specular weight x confidence", "[composite]") {
  const CompositeFixture f;
  const CompositeOutputs out = f.Run();
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 8; ++x) {
      for (int c = 0; c < 3; ++c) {
        const float indirect = out.indirect.c[c].ConstRow(y)[x];
        CAPTURE(x, y, c);
        REQUIRE(std::isfinite(indirect));
        CHECK(out.result.c[c].ConstRow(y)[x] == f.direct.c[c].ConstRow(y)[x] + indirect);
        if (x >= 4 || (x == 0 && y == 0)) {
          CHECK(indirect == 0.0f);  // background, or no confident hit
        } else {
          // A mirror metal seen head-on reflects about its base colour (F0 = albedo) of the traced light.
          const float albedo = UnpackAlbedo(f.gbuffer.word[0].ConstRow(y)[x])[c];
          CHECK(indirect == Approx(2.0f * 0.5f * albedo).epsilon(0.05));
        }
      }
    }
  }
}

TEST_CASE("composite: reflections fade out just below the roughness cut-off", "[composite]") {
  CompositeFixture f;
  auto indirectAt = [&](float roughness) {
    f.gbuffer.word[1].MutableRow(1)[1] = PackNormalRoughness({0.0f, 0.0f, 1.0f}, roughness, NormalEncoding::kOct24);
    return f.Run().indirect.c[0].ConstRow(1)[1];
  };
  const float full = indirectAt(0.5f);
  CHECK(full > 0.0f);
  CHECK(indirectAt(0.65f) > 0.0f);
  CHECK(indirectAt(0.65f) < full);
  CHECK(indirectAt(0.7f) == 0.0f);
  CHECK(indirectAt(0.9f) == 0.0f);
}

TEST_CASE("composite: identical at 1, 2 and 3 threads", "[composite][determinism]") {
  const CompositeFixture f;
  std::vector<float> first;
  for (int threads : {1, 2, 3}) {
    const ThreadLimit limit(threads);
    const CompositeOutputs out = f.Run();
    std::vector<float> values;
    for (int c = 0; c < 3; ++c)
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) values.push_back(out.result.c[c].ConstRow(y)[x]);
    if (first.empty()) first = values;
    CHECK(values == first);
  }
}

}  // namespace
}  // namespace ssgi
