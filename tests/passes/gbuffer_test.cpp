// The G-buffer pass on its own: what the resolve writes at each pixel of a plane seen in
// perspective, against the plane's analytic depth and normal, the material's packed words, and the
// coverage of the plane's edges; background and encoding. The SIMD kernels (raster tile, resolve row)
// against their scalar definitions on every compiled target.
#include "passes/gbuffer.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "core/gltf_loader.h"
#include "core/parallel.h"
#include "core/procedural_mesh.h"
#include "core/texture.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

TEST_CASE("g-buffer: every pixel of a ground plane has its analytic depth and normal, its material's words",
          "[gbuffer]") {
  constexpr int kWidth = 64, kHeight = 48;
  constexpr float kHalf = 20.0f;
  CameraDesc camera;
  camera.position = {0.3f, 2.0f, 4.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  for (const NormalEncoding encoding : {NormalEncoding::kOct24, NormalEncoding::kXyz8}) {
    CAPTURE(int(encoding));
    test::TestScene scene = test::MakeScene(camera, kWidth, kHeight);
    scene.materials[0].baseColor = {0.7f, 0.4f, 0.2f};
    scene.materials[0].metallic = 0.25f;
    scene.materials[0].roughness = 0.3f;
    test::AddGround(scene.mesh, kHalf);
    const ViewProjection view = MakePerspective(scene.camera, kWidth, kHeight);
    GBufferOutputs out;
    const GBufferStats stats = RunGBuffer({scene, view}, {encoding}, out);
    const GBuffer& g = out.gbuffer;
    REQUIRE(g.width() == kWidth);
    REQUIRE(g.height() == kHeight);
    CHECK(g.normalEncoding == encoding);

    // The plane y = 0 in view space, in double.
    const glm::dmat4 toView(view.view);
    const glm::dvec3 planeNormal = glm::normalize(glm::dmat3(toView) * glm::dvec3(0.0, 1.0, 0.0));
    const glm::dvec3 planePoint(toView * glm::dvec4(0.0, 0.0, 0.0, 1.0));
    const glm::dmat4 toWorld = glm::inverse(toView);
    const double maxNormalError = encoding == NormalEncoding::kOct24 ? 0.07 : 0.4;  // degrees, docs/design.md §3
    size_t covered = 0, checked = 0;
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        CAPTURE(x, y);
        const glm::dvec3 direction(view.PixelRay(float(x) + 0.5f, float(y) + 0.5f).direction);
        const double t = glm::dot(planeNormal, planePoint) / glm::dot(planeNormal, direction);
        const glm::dvec3 world(toWorld * glm::dvec4(direction * t, 1.0));
        const double edge = std::max(std::fabs(world.x), std::fabs(world.z));
        const float depth = UnpackDepth(g.word[GBufferWord::kDepth].ConstRow(size_t(y))[x]);
        covered += depth != kBackgroundDepth;
        // Pixels whose centre is clearly on or off the plane; those near its far edge may go either way.
        if (t > 0.0 && edge < kHalf * 0.98) {
          ++checked;
          REQUIRE(depth != kBackgroundDepth);
          CHECK(double(depth) == Approx(t).epsilon(1e-3));  // float32 at grazing angles, as the Embree depth test
          const uint32_t w0 = g.word[GBufferWord::kAlbedoMetallic].ConstRow(size_t(y))[x],
                         w1 = g.word[GBufferWord::kNormalRoughness].ConstRow(size_t(y))[x];
          CHECK(w0 == PackAlbedoMetallic(scene.materials[0].baseColor, 0.25f));
          CHECK((w1 >> 24) == 77u);  // round(0.3 * 255)
          const double cosine = glm::dot(glm::dvec3(UnpackNormal(w1, encoding)), planeNormal);
          CHECK(std::acos(std::min(cosine, 1.0)) * 180.0 / 3.14159265358979 < maxNormalError);
          CHECK(g.word[GBufferWord::kShadowTerm].ConstRow(size_t(y))[x] == kShadowLit);
        } else if (t <= 0.0 || edge > kHalf * 1.02) {
          CHECK(depth == kBackgroundDepth);
          CHECK(g.word[GBufferWord::kAlbedoMetallic].ConstRow(size_t(y))[x] == 0u);
          CHECK(g.word[GBufferWord::kNormalRoughness].ConstRow(size_t(y))[x] == 0u);
        }
      }
    }
    CHECK(checked > size_t(kWidth * kHeight) / 2);
    CHECK(covered < size_t(kWidth * kHeight));  // the sky above the plane's far edge
    CHECK(stats.coveredPixels == covered);
    CHECK(stats.raster.trianglesIn == 2);
  }
}

// Both kernel paths of RunGBuffer on `scene` at each test size and normal encoding: every word of
// the G-buffer and the visibility buffer the same bytes on every target.
// With threadCounts, also the same bytes at 1 and 3 threads.
void CheckKernelPathsAgree(const Scene& scene,
                           const std::vector<glm::ivec2>& sizes = {glm::ivec2(1024, 1024), glm::ivec2(1, 1),
                                                                   glm::ivec2(67, 45), glm::ivec2(1023, 769)},
                           bool threadCounts = false) {
  for (const glm::ivec2 size : sizes) {
    const ViewProjection view = MakePerspective(scene.camera, size.x, size.y);
    for (const NormalEncoding encoding : {NormalEncoding::kOct24, NormalEncoding::kXyz8}) {
      // Specular anti-aliasing on with one encoding, off with the other: both paths of the resolve.
      const float kappa = encoding == NormalEncoding::kOct24 ? kSpecularAaKappa : 0.0f;
      const auto run = [&](KernelPath kernels) {
        GBufferOutputs out;
        RunGBuffer({scene, view}, {encoding, false, kappa}, out, kernels);
        return out;
      };
      const auto same = [](const GBufferOutputs& a, const GBufferOutputs& b) {
        for (int w = 0; w < 4; ++w)
          if (!test::SameBytes(a.gbuffer.word[w], b.gbuffer.word[w])) return false;
        return test::SameBytes(a.visibility.triangle, b.visibility.triangle) &&
               test::SameBytes(a.visibility.depthKey, b.visibility.depthKey);
      };
      CAPTURE(size.x, size.y, int(encoding), kappa);
      CHECK(test::TargetsWhereKernelPathsDiffer(run, same) == "");
      if (!threadCounts) continue;
      const GBufferOutputs reference = run(KernelPath::kSimd);
      for (const int threads : {1, 3}) {
        ThreadLimit limit(threads);
        CHECK(same(run(KernelPath::kSimd), reference));
      }
    }
  }
}

TEST_CASE("g-buffer: outputs kept from an earlier frame give the bytes of new ones", "[gbuffer]") {
  const Scene scene = test::LoadDefaultScene().scene;
  const ViewProjection view = MakePerspective(scene.camera, 67, 45);
  for (const KernelPath kernels : {KernelPath::kScalar, KernelPath::kSimd}) {
    CAPTURE(int(kernels));
    GBufferOutputs fresh, reused;
    RunGBuffer({scene, view}, {NormalEncoding::kXyz8}, fresh, kernels);
    // An earlier frame from elsewhere, its word 3 as a shadow pass leaves it.
    CameraDesc elsewhere = scene.camera;
    elsewhere.position = {3.0f, 0.5f, -2.0f};
    RunGBuffer({scene, MakePerspective(elsewhere, 67, 45)}, {NormalEncoding::kOct24}, reused, kernels);
    for (size_t y = 0; y < 45; ++y)
      std::fill_n(reused.gbuffer.word[GBufferWord::kShadowTerm].MutableRow(y), 67, 0x80000001u);
    RunGBuffer({scene, view}, {NormalEncoding::kXyz8}, reused, kernels);
    CHECK(reused.gbuffer.normalEncoding == NormalEncoding::kXyz8);
    for (int w = 0; w < 4; ++w) CHECK(test::SameBytes(reused.gbuffer.word[w], fresh.gbuffer.word[w]));
    CHECK(test::SameBytes(reused.visibility.triangle, fresh.visibility.triangle));
    CHECK(test::SameBytes(reused.visibility.depthKey, fresh.visibility.depthKey));
  }
}

TEST_CASE("g-buffer: the SIMD kernels give the scalar bytes on every target, default scene", "[gbuffer][simd]") {
  CheckKernelPathsAgree(test::LoadDefaultScene().scene);
}

// A torus knot of 364k triangles, whose vertex data (4.4 MB of view positions and normals) is more
// than the resolve twin expects the caches to keep: it asks for each vector's vertices ahead.
TEST_CASE("g-buffer: the SIMD kernels give the scalar bytes on every target, a mesh larger than the caches",
          "[gbuffer][simd]") {
  Scene scene;
  scene.mesh = MakeTorusKnot(1400, 130);
  scene.materials.push_back(Material{});
  scene.camera.position = {0.0f, -0.6f, 4.0f};
  scene.camera.target = {0.0f, 0.0f, 0.0f};
  CHECK(scene.mesh.positions.size() * 2 * sizeof(glm::vec3) > kGBufferCachedVertexBytes);
  CheckKernelPathsAgree(scene);
}

TEST_CASE("g-buffer: the SIMD kernels give the scalar bytes on every target, textured materials",
          "[gbuffer][simd]") {
  // The default scene with every other material textured (colour, metallic, roughness in turn) by
  // an 8x8 texture of random texels over UVs from the world position.
  Scene scene = test::LoadDefaultScene().scene;
  std::mt19937 rng(5);
  std::vector<uint8_t> rgba(8 * 8 * 4);
  for (uint8_t& texel : rgba) texel = uint8_t(rng());
  scene.textures.push_back(MakeTexture(8, 8, rgba, TextureEncoding::kSrgb));
  scene.textures.push_back(MakeTexture(8, 8, std::move(rgba), TextureEncoding::kLinear));
  for (size_t m = 0; m < scene.materials.size(); m += 2) {
    Material& material = scene.materials[m];
    if (m % 3 == 0) material.baseColorTexture = 0;
    if (m % 3 == 1) material.metallicTexture = 1;
    if (m % 3 == 2) material.roughnessTexture = 1;
  }
  for (size_t i = 0; i < scene.mesh.positions.size(); ++i) {
    const glm::vec3 p = scene.mesh.positions[i];
    scene.mesh.uvs[i] = {0.7f * p.x, 0.7f * (p.z + p.y)};
  }
  CheckKernelPathsAgree(scene);

  // Textures of 256 and 64 texels a side at 3 repeats per metre: pixels span several texels, so the
  // footprint picks and blends mip levels (to the board's grazing far end), and the vectors' UV
  // footprint must equal SurfaceResolver::At's.
  std::vector<uint8_t> large(256 * 256 * 4), medium(64 * 64 * 4);
  for (uint8_t& texel : large) texel = uint8_t(rng());
  for (uint8_t& texel : medium) texel = uint8_t(rng());
  scene.textures.push_back(MakeTexture(256, 256, std::move(large), TextureEncoding::kSrgb));
  scene.textures.push_back(MakeTexture(64, 64, std::move(medium), TextureEncoding::kLinear));
  for (Material& material : scene.materials) {
    if (material.baseColorTexture == 0) material.baseColorTexture = 2;
    if (material.metallicTexture == 1) material.metallicTexture = 3;
    if (material.roughnessTexture == 1) material.roughnessTexture = 3;
  }
  for (size_t i = 0; i < scene.mesh.positions.size(); ++i) {
    const glm::vec3 p = scene.mesh.positions[i];
    scene.mesh.uvs[i] = {3.0f * p.x, 3.0f * (p.z + p.y)};
  }
  CheckKernelPathsAgree(scene);
}

TEST_CASE(
    "g-buffer: normal maps and vertex colours give the same G-buffer bytes on both kernel paths and at any "
    "thread count",
    "[gbuffer][simd]") {
  // The default scene with a random normal map (scale 0.7) on every third material, vertex colours
  // on the next, textures on others, generated tangents.
  Scene scene = test::LoadDefaultScene().scene;
  std::mt19937 rng(11);
  std::vector<uint8_t> normals(32 * 32 * 4), colours(8 * 8 * 4);
  for (size_t i = 0; i < normals.size(); i += 4) {
    normals[i] = uint8_t(rng()), normals[i + 1] = uint8_t(rng()), normals[i + 2] = uint8_t(160 + rng() % 96);
    normals[i + 3] = 255;
  }
  for (uint8_t& t : colours) t = uint8_t(rng());
  scene.textures.push_back(MakeTexture(32, 32, std::move(normals), TextureEncoding::kLinear));
  scene.textures.push_back(MakeTexture(8, 8, std::move(colours), TextureEncoding::kSrgb));
  const int32_t normalMap = int32_t(scene.textures.size()) - 2, colourMap = normalMap + 1;
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    Material& material = scene.materials[m];
    if (m % 3 == 0) material.normalTexture = normalMap, material.normalScale = 0.7f;
    if (m % 3 == 1) material.vertexColors = true;
    if (m % 2 == 0) material.baseColorTexture = colourMap;
  }
  for (size_t i = 0; i < scene.mesh.positions.size(); ++i) {
    const glm::vec3 p = scene.mesh.positions[i];
    scene.mesh.uvs[i] = {1.3f * p.x, 1.3f * (p.z + p.y)};
    scene.mesh.colors.push_back(glm::vec3(float(rng() % 256) / 255.0f, 0.5f, float(rng() % 256) / 255.0f));
  }
  GenerateTangents(scene.mesh);
  CheckKernelPathsAgree(scene, {glm::ivec2(1, 1), glm::ivec2(67, 45), glm::ivec2(333, 197)}, true);
  // The normal map changes the normals it covers.
  const ViewProjection view = MakePerspective(scene.camera, 67, 45);
  GBufferOutputs mapped;
  RunGBuffer({scene, view}, {}, mapped);
  for (Material& material : scene.materials) material.normalTexture = kNoTexture;
  GBufferOutputs flat;
  RunGBuffer({scene, view}, {}, flat);
  CHECK_FALSE(test::SameBytes(mapped.gbuffer.word[1], flat.gbuffer.word[1]));
}

// The roughness byte of word 1 as GGX alpha^2 = roughness^4, at the bottom of its code's interval:
// the least the packed roughness can have been.
double LeastAlphaSquared(uint32_t word1) {
  const double least = std::max(0.0, (double(word1 >> 24) - 0.5) / 255.0);
  return least * least * least * least;
}

TEST_CASE(
    "g-buffer: specular anti-aliasing raises a distant sphere's roughness most where its normal turns fastest, by "
    "at most kappa, and flat faces and kappa 0 keep the material's code",
    "[gbuffer]") {
  // The default scene from three times as far: its spheres and chess pieces are a few dozen pixels
  // across, their normals turning by degrees per pixel; the board and the boxes are flat.
  Scene scene = test::LoadDefaultScene().scene;
  scene.camera.position = scene.camera.target + (scene.camera.position - scene.camera.target) * 3.0f;
  constexpr int kWidth = 256, kHeight = 192;
  const ViewProjection view = MakePerspective(scene.camera, kWidth, kHeight);
  const float kappa = kSpecularAaKappa;
  GBufferOutputs on, off;
  RunGBuffer({scene, view}, {NormalEncoding::kOct24, false, kappa}, on);
  RunGBuffer({scene, view}, {NormalEncoding::kOct24, false, 0.0f}, off);
  size_t curvedPixels = 0, raised = 0, atKappa = 0;
  double facingSum = 0.0, grazingSum = 0.0;
  size_t facing = 0, grazing = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      CAPTURE(x, y);
      const uint32_t triangle = on.visibility.triangle.ConstRow(size_t(y))[x];
      const uint32_t w1 = on.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(size_t(y))[x];
      const uint32_t w1Off = off.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(size_t(y))[x];
      // Off: every word the same but the roughness byte, which is the material's.
      for (const int w : {0, 2, 3})
        CHECK(on.gbuffer.word[w].ConstRow(size_t(y))[x] == off.gbuffer.word[w].ConstRow(size_t(y))[x]);
      CHECK((w1 & 0xFFFFFFu) == (w1Off & 0xFFFFFFu));
      if (triangle == kNoTriangle) continue;
      const Material& material = scene.materials[scene.mesh.materials[triangle]];
      REQUIRE((w1Off >> 24) == UnormCode8(material.roughness));
      const uint32_t* idx = &scene.mesh.indices[3 * size_t(triangle)];
      const bool flat = scene.mesh.normals[idx[0]] == scene.mesh.normals[idx[1]] &&
                        scene.mesh.normals[idx[0]] == scene.mesh.normals[idx[2]];
      if (flat) {
        CHECK(w1 == w1Off);
        continue;
      }
      ++curvedPixels;
      CHECK((w1 >> 24) >= (w1Off >> 24));
      raised += (w1 >> 24) > (w1Off >> 24);
      const double r = material.roughness, added = LeastAlphaSquared(w1) - r * r * r * r;
      CHECK(added <= double(kappa) + 1e-6);
      atKappa += (w1 >> 24) == UnormCode8(WidenedRoughness(material.roughness, 1.0f, kappa));
      // Where the view-space normal faces the camera the sphere turns slowest across a pixel; toward
      // the silhouette fastest.
      const float towardCamera = UnpackNormal(w1, NormalEncoding::kOct24).z;
      const double widened = double(w1 >> 24) - double(w1Off >> 24);
      if (towardCamera > 0.9f) facingSum += widened, ++facing;
      if (towardCamera < 0.4f) grazingSum += widened, ++grazing;
    }
  }
  CHECK(curvedPixels > 400);
  CHECK(raised > curvedPixels / 4);
  CHECK(atKappa > 0);
  REQUIRE(facing > 50);
  REQUIRE(grazing > 50);
  CHECK(facingSum > 0.0);
  CHECK(grazingSum / double(grazing) > 1.2 * (facingSum / double(facing)));
}

TEST_CASE(
    "g-buffer: specular anti-aliasing raises a noisy normal map's roughness where its coarse mips average the "
    "texels (Toksvig), and leaves a flat map's",
    "[gbuffer]") {
  // A ground plane, flat (no curvature), under a 64x64 normal map of random directions in the upper
  // hemisphere, 16 texels per metre: near the camera a texel covers pixels (level 0), toward the
  // horizon a pixel covers many texels (coarse levels, whose texels are averages, shorter than unit).
  CameraDesc camera;
  camera.position = {0.0f, 1.0f, 3.0f};
  camera.target = {0.0f, 0.0f, -4.0f};
  constexpr int kWidth = 96, kHeight = 72;
  test::TestScene scene = test::MakeScene(camera, kWidth, kHeight);
  scene.materials[0].roughness = 0.2f;
  test::AddGround(scene.mesh, 20.0f);
  for (size_t i = 0; i < scene.mesh.positions.size(); ++i)
    scene.mesh.uvs[i] = {0.25f * scene.mesh.positions[i].x, 0.25f * scene.mesh.positions[i].z};
  GenerateTangents(scene.mesh);
  std::mt19937 rng(3);
  std::vector<uint8_t> noisy(64 * 64 * 4), level(64 * 64 * 4);
  for (size_t i = 0; i < noisy.size(); i += 4) {
    const glm::vec3 n =
        glm::normalize(glm::vec3(float(rng() % 201) / 100.0f - 1.0f, float(rng() % 201) / 100.0f - 1.0f, 1.2f));
    for (int c = 0; c < 3; ++c) noisy[i + size_t(c)] = uint8_t(std::lround((n[c] * 0.5f + 0.5f) * 255.0f));
    noisy[i + 3] = 255;
    level[i] = level[i + 1] = 128, level[i + 2] = 255, level[i + 3] = 255;
  }
  scene.textures.push_back(MakeTexture(64, 64, std::move(noisy), TextureEncoding::kLinear));
  scene.textures.push_back(MakeTexture(64, 64, std::move(level), TextureEncoding::kLinear));
  const ViewProjection view = MakePerspective(scene.camera, kWidth, kHeight);
  const float kappa = kSpecularAaKappa;
  const auto roughnessCodes = [&](int32_t normalTexture) {
    scene.materials[0].normalTexture = normalTexture;
    GBufferOutputs out;
    RunGBuffer({scene, view}, {NormalEncoding::kOct24, false, kappa}, out);
    std::vector<int> codes;  // per pixel, -1 on the background
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x)
        codes.push_back(out.visibility.triangle.ConstRow(size_t(y))[x] == kNoTriangle
                            ? -1
                            : int(out.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(size_t(y))[x] >> 24));
    return codes;
  };
  const int materialCode = UnormCode8(0.2f);
  for (const int code : roughnessCodes(1)) CHECK((code == -1 || code == materialCode));
  const std::vector<int> codes = roughnessCodes(0);
  const int mostCode = UnormCode8(WidenedRoughness(0.2f, 1.0f, kappa));
  // The rows near the horizon (coarse mips) against those at the bottom (level 0), with the plane.
  double farSum = 0.0, nearSum = 0.0;
  size_t farCount = 0, nearCount = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const int code = codes[size_t(y * kWidth + x)];
      if (code < 0) continue;
      CHECK(code >= materialCode);
      CHECK(code <= mostCode);
      if (y < kHeight / 2) farSum += code - materialCode, ++farCount;
      if (y >= kHeight - 8) nearSum += code - materialCode, ++nearCount;
    }
  }
  REQUIRE(farCount > 0);
  REQUIRE(nearCount > 0);
  CHECK(farSum / double(farCount) > 2.0 * nearSum / double(nearCount));
  CHECK(farSum / double(farCount) > 10.0);
}

}  // namespace
}  // namespace ssgi

namespace ssgi {
namespace {

// Sibenik's steps show isolated black pixels along their edges in a one-sample-per-pixel image.
// They are the steps' real geometry: under each step's front lip a 1 cm bevel faces down and away
// from the only light, thinner than a pixel, so a pixel centre falls on it here and there. This
// pins that reading: every pixel whose stored normal points down lies on a triangle whose own
// (geometric) normal points down, never on an upward face given a flipped normal, and its direct
// light is exactly 0. (A smooth normal may lean down on faces beside such a bevel: the test looks
// at normals more than 60 degrees below the horizon.)
TEST_CASE("g-buffer: Sibenik's downward-facing pixels are its downward-facing triangles", "[gbuffer][real_scenes]") {
  const std::filesystem::path file = test::SourceDir() / "data" / "scenes" / "sibenik.json";
  if (!std::filesystem::exists(test::ThirdPartyScenesDir() / "sibenik-cathedral" / "sibenik.obj")) {
    WARN(test::MissingScenesMessage(test::ThirdPartyScenesDir() / "sibenik-cathedral"));
    return;
  }
  SceneFile loaded = LoadSceneFile(file);
  FrameConfig config = FrameConfigFromSceneFile(loaded);
  config.shadows = EffectMode::kOff;
  config.reflections = EffectMode::kOff;
  const Scene& scene = loaded.scene;
  const Frame frame = RenderFrame(scene, config);
  const GBuffer& g = frame.gbuffer.gbuffer;
  const glm::mat3 viewToWorld = glm::transpose(glm::mat3(frame.view.view));
  // The steps at the front of the default camera's 1024x1024 view.
  REQUIRE(g.width() == 1024);
  REQUIRE(g.height() == 1024);
  size_t downward = 0;
  for (int y = 585; y < 665; ++y) {
    for (int x = 410; x < 620; ++x) {
      if (UnpackDepth(g.word[GBufferWord::kDepth].ConstRow(y)[x]) == kBackgroundDepth) continue;
      const glm::vec3 normal =
          viewToWorld * UnpackNormal(g.word[GBufferWord::kNormalRoughness].ConstRow(y)[x], g.normalEncoding);
      if (normal.y > -0.87f) continue;
      ++downward;
      const uint32_t triangle = frame.gbuffer.visibility.triangle.ConstRow(y)[x];
      const glm::vec3 a = scene.mesh.positions[scene.mesh.indices[3 * triangle]];
      const glm::vec3 b = scene.mesh.positions[scene.mesh.indices[3 * triangle + 1]];
      const glm::vec3 c = scene.mesh.positions[scene.mesh.indices[3 * triangle + 2]];
      const glm::vec3 face = glm::normalize(glm::cross(b - a, c - a));
      CAPTURE(x, y, triangle, normal.x, normal.y, normal.z, face.x, face.y, face.z);
      CHECK(face.y < 0.0f);
      for (int channel = 0; channel < 3; ++channel) CHECK(frame.direct.radiance.c[channel].ConstRow(y)[x] == 0.0f);
    }
  }
  CHECK(downward > 0);
}

}  // namespace
}  // namespace ssgi
