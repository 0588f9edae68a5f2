// The composite on a hand-made G-buffer (result = direct + weighted reflection, the roughness fade,
// the bounce's terms, thread counts); the SIMD kernel against the scalar one on every target, on
// random rows of every length up to a few vectors, with and without the bounce, and the whole pass
// on the default scene's buffers at several sizes.
#include "passes/composite.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "core/parallel.h"
#include "passes/bounce.h"
#include "passes/ssr_trace.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

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
        gbuffer.word[GBufferWord::kAlbedoMetallic].MutableRow(y)[x] =
            PackAlbedoMetallic(glm::vec3(0.9f, 0.6f, 0.3f), 1.0f);
        gbuffer.word[GBufferWord::kNormalRoughness].MutableRow(y)[x] =
            PackNormalRoughness({0.0f, 0.0f, 1.0f}, 0.0f, NormalEncoding::kOct24);
        gbuffer.word[GBufferWord::kDepth].MutableRow(y)[x] = PackDepth(3.0f);
      }
    }
    confidence.MutableRow(0)[0] = 0.0f;
  }
  CompositeOutputs Run() const {
    CompositeOutputs out;
    RunComposite({gbuffer, view, direct, &reflected, &confidence, 0.7f}, out);
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
          const float albedo = UnpackAlbedo(f.gbuffer.word[GBufferWord::kAlbedoMetallic].ConstRow(y)[x])[c];
          CHECK(indirect == Approx(2.0f * 0.5f * albedo).epsilon(0.05));
        }
      }
    }
  }
}

TEST_CASE("composite: reflections fade out just below the roughness cut-off", "[composite]") {
  CompositeFixture f;
  auto indirectAt = [&](float roughness) {
    f.gbuffer.word[GBufferWord::kNormalRoughness].MutableRow(1)[1] =
        PackNormalRoughness({0.0f, 0.0f, 1.0f}, roughness, NormalEncoding::kOct24);
    return f.Run().indirect.c[0].ConstRow(1)[1];
  };
  const float full = indirectAt(0.5f);
  CHECK(full > 0.0f);
  CHECK(indirectAt(0.65f) > 0.0f);
  CHECK(indirectAt(0.65f) < full);
  CHECK(indirectAt(0.7f) == 0.0f);
  CHECK(indirectAt(0.9f) == 0.0f);
}

TEST_CASE("composite: where the trace saw nothing, a glossy surface reflects the surroundings' light", "[composite]") {
  const CompositeFixture f;
  // Under a black sky the environment sends nothing; the interreflection volume's light towards the
  // mirror direction fills the share the trace did not see, 1 - confidence (the fade is 1 at
  // roughness 0), whatever the sky's visibility.
  const EnvironmentLighting black = PrepareEnvironmentLighting(ConstantEnvironment(glm::vec3(0.0f)));
  const Plane<float> hidden = MakePlane<float>(8, 4, 0.0f);
  const Plane3<float> surroundings = MakePlane3<float>(8, 4, 0.75f);
  CompositeInputs inputs{f.gbuffer, f.view, f.direct, &f.reflected, &f.confidence, 0.7f, nullptr, &black, &hidden};
  CompositeOutputs traced;
  RunComposite(inputs, traced);
  inputs.skyReflected = &surroundings;
  CompositeOutputs filled;
  RunComposite(inputs, filled);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x)
      for (int c = 0; c < 3; ++c) {
        CAPTURE(x, y, c);
        const float added = filled.indirect.c[c].ConstRow(y)[x] - traced.indirect.c[c].ConstRow(y)[x];
        if (x >= 4) {
          CHECK(added == 0.0f);  // background
          continue;
        }
        // The mirror metal head-on reflects about its base colour of what arrives.
        const float albedo = UnpackAlbedo(f.gbuffer.word[GBufferWord::kAlbedoMetallic].ConstRow(y)[x])[c];
        const float unseen = 1.0f - f.confidence.ConstRow(y)[x];
        CHECK(added == Approx(0.75f * unseen * albedo).epsilon(0.05));
      }
}

TEST_CASE("composite: the bounce adds its light on the diffuse albedo and darkens the sky's diffuse light",
          "[composite]") {
  CompositeFixture f;
  // Pixel (1, 1): a rough dielectric, which reflects nothing traced (past the cut-off).
  f.gbuffer.word[GBufferWord::kAlbedoMetallic].MutableRow(1)[1] = PackAlbedoMetallic(glm::vec3(0.8f, 0.4f, 0.2f), 0.0f);
  f.gbuffer.word[GBufferWord::kNormalRoughness].MutableRow(1)[1] =
      PackNormalRoughness({0.0f, 0.0f, 1.0f}, 0.9f, NormalEncoding::kOct24);
  const Plane3<float> bounce = MakePlane3<float>(8, 4, 0.5f);
  const Plane3<float> skyDiffuse = MakePlane3<float>(8, 4, 0.125f);
  const Plane<float> visibility = MakePlane<float>(8, 4, 0.25f);
  const CompositeOutputs without = f.Run();
  CompositeInputs inputs{f.gbuffer, f.view, f.direct, &f.reflected, &f.confidence, 0.7f};
  inputs.bounce = &bounce;
  CompositeOutputs bounceOnly;
  RunComposite(inputs, bounceOnly);
  inputs.skyDiffuse = &skyDiffuse;
  inputs.ambientVisibility = &visibility;
  CompositeOutputs both;
  RunComposite(inputs, both);
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 8; ++x) {
      const uint32_t word0 = f.gbuffer.word[GBufferWord::kAlbedoMetallic].ConstRow(y)[x];
      for (int c = 0; c < 3; ++c) {
        CAPTURE(x, y, c);
        const float direct = f.direct.c[c].ConstRow(y)[x];
        if (x >= 4) {
          // Background: neither term.
          CHECK(bounceOnly.indirect.c[c].ConstRow(y)[x] == 0.0f);
          CHECK(both.result.c[c].ConstRow(y)[x] == direct);
          continue;
        }
        // The metal's diffuse albedo is 0: its pixels keep their reflection and gain nothing.
        const float diffuseAlbedo = UnpackAlbedo(word0)[c] * (1.0f - UnpackMetallic(word0));
        const float expectedIndirect = without.indirect.c[c].ConstRow(y)[x] + 0.5f * diffuseAlbedo;
        CHECK(bounceOnly.indirect.c[c].ConstRow(y)[x] == expectedIndirect);
        CHECK(bounceOnly.result.c[c].ConstRow(y)[x] == direct + expectedIndirect);
        CHECK(both.indirect.c[c].ConstRow(y)[x] == expectedIndirect);
        // The sky's diffuse light kept at the visibility's share: 0.125 x 0.25 of it, 0.125 x 0.75 taken.
        CHECK(both.result.c[c].ConstRow(y)[x] == (direct + 0.125f * -0.75f) + expectedIndirect);
      }
    }
  }
  CHECK(UnpackMetallic(f.gbuffer.word[GBufferWord::kAlbedoMetallic].ConstRow(1)[1]) == 0.0f);
  CHECK(both.indirect.c[0].ConstRow(1)[1] == Approx(0.5f * 0.8f).epsilon(0.01));
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

// [0, end) for every end, and [32, end) for every end past 32.
std::vector<std::pair<int, int>> RunsOfRow(int width) {
  std::vector<std::pair<int, int>> runs;
  for (int begin : {0, TileMask::kTileSize})
    for (int end = begin + 1; end <= width; ++end) runs.emplace_back(begin, end);
  return runs;
}

TEST_CASE("composite: the SIMD kernel equals the scalar kernel on every target", "[composite][simd]") {
  constexpr int kWidth = 70;  // a few vectors of every target, and a tail
  std::mt19937 rng(22);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), radiance(0.0f, 8.0f);
  // Float input rows: confidence, direct and reflected RGB, the bounce RGB, the sky's diffuse light
  // RGB and the bounce's visibility; output rows: indirect, result.
  std::vector<std::vector<float>> in(14, std::vector<float>(kWidth));
  size_t compared = 0;
  for (const ViewProjection& view : test::TwinTestViews(kWidth, 50)) {
    for (const NormalEncoding encoding : {NormalEncoding::kXyz8, NormalEncoding::kOct24}) {
      for (const float cutoff : {0.7f, 1.0f}) {
        for (const size_t y : {size_t(0), size_t(17), size_t(49)}) {
          // A confidence of 0 (no hit), 1 or between; a visibility of 0, 1 or between.
          const test::RandomGBufferRow words(kWidth, rng);
          for (int x = 0; x < kWidth; ++x) {
            in[0][x] = x % 3 == 0 ? 0.0f : x % 7 == 0 ? 1.0f : unit(rng);
            for (int c = 1; c < 13; ++c) in[c][x] = radiance(rng);
            in[13][x] = x % 5 == 0 ? 1.0f : x % 11 == 0 ? 0.0f : unit(rng);
          }
          const CompositeContext context{view, encoding, cutoff};
          // Without the bounce, with it, and with it darkening the sky's diffuse light.
          for (const int bounceTerms : {0, 1, 2}) {
            // Runs from the row's start and from a tile edge (a tile mask's runs), of every length.
            for (const auto& [begin, end] : RunsOfRow(kWidth)) {
              // Every output row is filled past the row's end, which must stay as it is.
              std::vector<float> expected(6 * kWidth, -1.0f), actual(6 * kWidth);
              const auto rowOf = [&](std::vector<float>& out) {
                CompositeRow row{words.word[GBufferWord::kAlbedoMetallic].data(),
                                 words.word[GBufferWord::kNormalRoughness].data(),
                                 words.word[GBufferWord::kDepth].data(),
                                 in[0].data(),
                                 nullptr,
                                 {nullptr, nullptr, nullptr},
                                 {in[1].data(), in[2].data(), in[3].data()},
                                 {in[4].data(), in[5].data(), in[6].data()},
                                 {&out[0], &out[kWidth], &out[2 * kWidth]},
                                 {&out[3 * kWidth], &out[4 * kWidth], &out[5 * kWidth]},
                                 {nullptr, nullptr, nullptr},
                                 {nullptr, nullptr, nullptr},
                                 nullptr};
                if (bounceTerms >= 1) {
                  for (int c = 0; c < 3; ++c) row.bounce[c] = in[size_t(7 + c)].data();
                }
                if (bounceTerms == 2) {
                  for (int c = 0; c < 3; ++c) row.skyDiffuse[c] = in[size_t(10 + c)].data();
                  row.ambientVisibility = in[13].data();
                }
                return row;
              };
              CompositeRowScalar(context, rowOf(expected), y, begin, end);
              test::ForEachSimdTarget([&](const char* target) {
                std::fill(actual.begin(), actual.end(), -1.0f);
                CompositeRowSimd(context, rowOf(actual), y, begin, end);
                const size_t first = test::FirstDifferentBits(actual.data(), expected.data(), actual.size());
                CAPTURE(target, view.orthographic, int(encoding), cutoff, y, bounceTerms, begin, end, first);
                REQUIRE(first == actual.size());
                ++compared;
              });
            }
          }
        }
      }
    }
  }
  CHECK(compared >= 2 * 2 * 2 * 3 * 3 * kWidth);
}

CompositeOutputs RunCompositeOn(const Frame& frame, KernelPath kernels) {
  CompositeOutputs out;
  RunComposite({frame.gbuffer.gbuffer, frame.view, frame.direct.radiance, &frame.ssrCone.reflected,
                &frame.ssrTrace.confidence, SsrTraceParams{}.roughnessCutoff},
               out, kernels);
  return out;
}

TEST_CASE("composite: the SIMD pass gives the scalar pass's bytes on the default scene on every target",
          "[composite][simd]") {
  const test::DefaultScene scene = test::LoadDefaultScene();
  for (const auto& [width, height] : {std::pair{1024, 1024}, {1, 1}, {67, 45}, {1023, 769}}) {
    const Frame frame = scene.Render(width, height);
    REQUIRE(frame.reflections);
    const CompositeOutputs scalar = RunCompositeOn(frame, KernelPath::kScalar);
    const size_t targets = test::ForEachSimdTarget([&](const char* target) {
      const CompositeOutputs simd = RunCompositeOn(frame, KernelPath::kSimd);
      for (int c = 0; c < 3; ++c) {
        CAPTURE(target, width, height, c);
        CHECK(test::SameBytes(simd.indirect.c[c], scalar.indirect.c[c]));
        CHECK(test::SameBytes(simd.result.c[c], scalar.result.c[c]));
      }
    });
    CHECK(targets >= 1);
  }
}

TEST_CASE(
    "composite: with the sky's light (a constant or a sky environment), the surroundings' reflected light and the "
    "bounce, the SIMD pass gives the scalar bytes",
    "[composite][simd]") {
  const test::DefaultScene scene = test::LoadDefaultScene();
  SkyParams skyParams;
  skyParams.sunGlow = glm::vec3(4.0f, 3.0f, 2.0f);
  const EnvironmentLighting sky = PrepareEnvironmentLighting(MakeSkyEnvironment(skyParams), {32, 16, 16});
  const EnvironmentLighting constant = PrepareEnvironmentLighting(ConstantEnvironment(glm::vec3(0.2f, 0.3f, 0.4f)));
  for (const auto& [width, height] : {std::pair{67, 45}, {1, 1}, {173, 91}}) {
    const Frame frame = scene.Render(width, height);
    REQUIRE(frame.reflections);
    REQUIRE(frame.sky);
    REQUIRE(frame.skyLight.reflected.c[0].xsize() == size_t(width));
    // A sky visibility that varies.
    Plane<float> visibility = MakePlane<float>(size_t(width), size_t(height), 0.0f);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) visibility.MutableRow(size_t(y))[x] = float((x * 7 + y * 3) % 11) / 10.0f;
    BounceOutputs bounce;
    RunBounce({frame.gbuffer.gbuffer, frame.view, frame.Lit()}, {}, bounce);
    for (const EnvironmentLighting* environment : {&sky, &constant, static_cast<const EnvironmentLighting*>(nullptr)}) {
      for (const bool reflections : {true, false}) {
        for (const int bounceTerms : {0, 1, 2}) {
          for (const bool surroundings : {false, true}) {
            if (!environment && !reflections && bounceTerms == 0) continue;  // the composite would not run
            if (surroundings && !environment) continue;
            const auto run = [&](KernelPath kernels) {
              CompositeInputs inputs{frame.gbuffer.gbuffer,
                                     frame.view,
                                     frame.Lit(),
                                     reflections ? &frame.ssrCone.reflected : nullptr,
                                     reflections ? &frame.ssrTrace.confidence : nullptr,
                                     SsrTraceParams{}.roughnessCutoff,
                                     nullptr,
                                     environment,
                                     environment ? &visibility : nullptr};
              if (surroundings) inputs.skyReflected = &frame.skyLight.reflected;
              if (bounceTerms >= 1) inputs.bounce = &bounce.bounce;
              if (bounceTerms == 2) {
                inputs.skyDiffuse = &frame.skyLight.diffuse;
                inputs.ambientVisibility = &bounce.visibility;
              }
              CompositeOutputs out;
              RunComposite(inputs, out, kernels);
              return out;
            };
            const auto same = [](const CompositeOutputs& a, const CompositeOutputs& b) {
              bool equal = true;
              for (int c = 0; c < 3; ++c)
                equal = equal && test::SameBytes(a.indirect.c[c], b.indirect.c[c]) &&
                        test::SameBytes(a.result.c[c], b.result.c[c]);
              return equal;
            };
            CAPTURE(width, height, environment ? int(environment->constant) : -1, reflections, bounceTerms,
                    surroundings);
            CHECK(test::TargetsWhereKernelPathsDiffer(run, same).empty());
          }
        }
      }
    }
  }
}

TEST_CASE("composite: a bounce of 0 at visibility 1 leaves the composite's bytes as they are without the bounce",
          "[composite]") {
  const test::DefaultScene scene = test::LoadDefaultScene();
  const Frame frame = scene.Render(67, 45);
  REQUIRE(frame.reflections);
  REQUIRE(frame.sky);
  const Plane3<float> zero = MakePlane3<float>(67, 45, 0.0f);
  const Plane<float> open = MakePlane<float>(67, 45, 1.0f);
  for (const KernelPath kernels : {KernelPath::kScalar, KernelPath::kSimd}) {
    CompositeInputs inputs{frame.gbuffer.gbuffer,
                           frame.view,
                           frame.Lit(),
                           &frame.ssrCone.reflected,
                           &frame.ssrTrace.confidence,
                           SsrTraceParams{}.roughnessCutoff,
                           nullptr,
                           &frame.environment,
                           &frame.skyLight.visibility};
    CompositeOutputs without, with;
    RunComposite(inputs, without, kernels);
    inputs.bounce = &zero;
    inputs.skyDiffuse = &frame.skyLight.diffuse;
    inputs.ambientVisibility = &open;
    RunComposite(inputs, with, kernels);
    for (int c = 0; c < 3; ++c) {
      CAPTURE(int(kernels), c);
      CHECK(test::SameBytes(with.indirect.c[c], without.indirect.c[c]));
      CHECK(test::SameBytes(with.result.c[c], without.result.c[c]));
    }
  }
}

TEST_CASE("composite: in place over the direct image and the reflection, the same bytes on every target",
          "[composite][simd][memory]") {
  const test::DefaultScene scene = test::LoadDefaultScene();
  for (const auto& [width, height] : {std::pair{1, 1}, {67, 45}, {1023, 769}}) {
    const Frame frame = scene.Render(width, height);
    REQUIRE(frame.reflections);
    REQUIRE(frame.bounce);
    for (KernelPath kernels : {KernelPath::kScalar, KernelPath::kSimd}) {
      const size_t targets = test::ForEachSimdTarget([&](const char* target) {
        // The frame's memory-saving hand-over: the outputs are the inputs' own planes.
        CompositeOutputs inPlace;
        inPlace.result = test::CopyOf(frame.Lit());
        inPlace.indirect = test::CopyOf(frame.ssrCone.reflected);
        CompositeInputs inputs{frame.gbuffer.gbuffer,
                               frame.view,
                               inPlace.result,
                               &inPlace.indirect,
                               &frame.ssrTrace.confidence,
                               SsrTraceParams{}.roughnessCutoff,
                               nullptr,
                               frame.sky ? &frame.environment : nullptr,
                               frame.sky ? &frame.skyLight.visibility : nullptr};
        if (frame.sky) inputs.skyReflected = &frame.skyLight.reflected;
        if (frame.bounce) {
          inputs.bounce = &frame.diffuseBounce.bounce;
          inputs.skyDiffuse = frame.sky ? &frame.skyLight.diffuse : nullptr;
          inputs.ambientVisibility = frame.sky ? &frame.diffuseBounce.visibility : nullptr;
        }
        RunComposite(inputs, inPlace, kernels);
        for (int c = 0; c < 3; ++c) {
          CAPTURE(target, width, height, c);
          CHECK(test::SameBytes(inPlace.indirect.c[c], frame.composite.indirect.c[c]));
          CHECK(test::SameBytes(inPlace.result.c[c], frame.composite.result.c[c]));
        }
      });
      CHECK(targets >= 1);
    }
  }
}

}  // namespace
}  // namespace ssgi
