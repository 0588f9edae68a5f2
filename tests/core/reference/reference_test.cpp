// The Embree reference (core/reference/reference.h): primary visibility against the rasterizer, direct light
// against analytic values, area-light soft shadows, Monte Carlo convergence, determinism and
// finiteness in degenerate set-ups.
#include "core/reference/reference.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <utility>
#include <vector>

#include "core/brdf.h"
#include "core/gbuffer.h"
#include "core/lighting.h"
#include "core/parallel.h"
#include "core/procedural_mesh.h"
#include "core/scene.h"
#include "passes/frame/frame.h"
#include "passes/gbuffer.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

using test::AddBox;
using test::AddGround;
using test::AddQuad;
using test::LightDirection;
using test::ConfigOf;
using test::MakeScene;
using test::Sized;
using test::Sun;
using test::TestScene;

// The reference of a test scene at the size and background it is rendered with.
ReferenceOutputs RenderReferenceOf(const TestScene& scene, ReferenceParams params,
                                   const ReferenceProgress& progress = nullptr) {
  params.width = scene.width;
  params.height = scene.height;
  params.environment = ConstantEnvironment(scene.background);
  return RenderReference(scene, params, progress);
}

CameraDesc Camera(glm::vec3 position, glm::vec3 target, float fovYDegrees) {
  CameraDesc c;
  c.position = position;
  c.target = target;
  c.fovYDegrees = fovYDegrees;
  return c;
}

// Appends `part` to `mesh` with every triangle using `material`.
void Append(Mesh& mesh, const Mesh& part, uint32_t material) {
  const uint32_t base = uint32_t(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), part.positions.begin(), part.positions.end());
  mesh.normals.insert(mesh.normals.end(), part.normals.begin(), part.normals.end());
  mesh.uvs.insert(mesh.uvs.end(), part.uvs.begin(), part.uvs.end());
  for (uint32_t i : part.indices) mesh.indices.push_back(base + i);
  mesh.materials.insert(mesh.materials.end(), part.TriangleCount(), material);
}

Mesh Translated(Mesh mesh, glm::vec3 offset, float scale) {
  for (glm::vec3& p : mesh.positions) p = p * scale + offset;
  return mesh;
}

uint32_t AddMaterial(Scene& scene, glm::vec3 baseColor, float metallic, float roughness, bool twoSided) {
  Material m;
  m.baseColor = baseColor;
  m.metallic = metallic;
  m.roughness = roughness;
  m.twoSided = twoSided;
  scene.materials.push_back(m);
  return uint32_t(scene.materials.size() - 1);
}

// A quad with UVs over [0, tiles]^2, cut out by an 8x8 checker alpha texture.
void AddCutOutQuad(Scene& scene, glm::vec3 o, glm::vec3 u, glm::vec3 v, float tiles) {
  std::vector<uint8_t> rgba(8 * 8 * 4, 255);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) rgba[(size_t(y) * 8 + x) * 4 + 3] = ((x + y) % 2) ? 255 : 0;
  scene.textures.push_back(MakeTexture(8, 8, std::move(rgba), TextureEncoding::kLinear));
  const uint32_t material = AddMaterial(scene, glm::vec3(0.6f, 0.7f, 0.3f), 0.0f, 0.6f, true);
  scene.materials[material].alphaTexture = int32_t(scene.textures.size() - 1);
  Mesh quad;
  AddQuad(quad, o, u, v);
  quad.uvs = {{0, 0}, {tiles, 0}, {tiles, tiles}, {0, tiles}};
  Append(scene.mesh, quad, material);
}

// Materials of FeatureScene: ground 0, box 1, then these.
constexpr uint32_t kAwayMaterial = 2;
constexpr uint32_t kCutOutMaterial = 3;

// Ground (two-sided, material 0), a box, a single-sided quad facing away from the camera (invisible
// to it), a cut-out quad, a torus knot; a sun and a spot light.
TestScene FeatureScene(int width, int height) {
  TestScene scene = MakeScene(Camera({0.6f, 2.2f, 4.5f}, {0.0f, 0.4f, 0.0f}, 45.0f), width, height);
  scene.materials[0].baseColor = glm::vec3(0.7f);
  scene.materials[0].roughness = 0.4f;
  AddGround(scene.mesh, 3.0f);
  Mesh box;
  AddBox(box, {-1.4f, 0.0f, -0.6f}, {-0.6f, 0.8f, 0.2f});
  Append(scene.mesh, box, AddMaterial(scene, {0.95f, 0.64f, 0.54f}, 1.0f, 0.25f, false));
  Mesh away;
  AddQuad(away, {0.6f, 0.2f, 1.2f}, {0.0f, 0.6f, 0.0f}, {0.6f, 0.0f, 0.0f});  // faces -z, camera is at +z
  Append(scene.mesh, away, AddMaterial(scene, {0.2f, 0.9f, 0.2f}, 0.0f, 0.5f, false));
  AddCutOutQuad(scene, {0.3f, 0.05f, -1.2f}, {1.2f, 0.0f, 0.0f}, {0.0f, 1.2f, 0.0f}, 3.0f);
  Append(scene.mesh, Translated(MakeTorusKnot(64, 8), {1.0f, 0.7f, 0.2f}, 0.35f),
         AddMaterial(scene, {0.9f, 0.9f, 0.9f}, 1.0f, 0.1f, false));
  scene.directionalLights.push_back(Sun(LightDirection(40.0f, 30.0f), 4.0f));
  SpotLight spot;
  spot.position = {-0.5f, 2.5f, 1.0f};
  spot.direction = glm::normalize(glm::vec3(0.3f, -1.0f, -0.3f));
  spot.radius = 0.15f;
  spot.intensity = glm::vec3(6.0f, 5.0f, 4.0f);
  scene.spotLights.push_back(spot);
  scene.background = {0.05f, 0.06f, 0.08f};
  return scene;
}

bool IsBackground(float depth) { return !(depth < kBackgroundDepth); }

// Root mean square difference over every channel of every pixel.
double Rmse(const Plane3<float>& a, const Plane3<float>& b) {
  double sum = 0.0;
  size_t n = 0;
  for (int c = 0; c < 3; ++c) {
    for (size_t y = 0; y < a.c[c].ysize(); ++y) {
      for (size_t x = 0; x < a.c[c].xsize(); ++x) {
        const double d = double(a.c[c].ConstRow(y)[x]) - double(b.c[c].ConstRow(y)[x]);
        sum += d * d;
        ++n;
      }
    }
  }
  return std::sqrt(sum / double(n));
}

template <class T>
bool SameBytes(const Plane<T>& a, const Plane<T>& b) {
  for (size_t y = 0; y < a.ysize(); ++y)
    if (std::memcmp(a.ConstRow(y), b.ConstRow(y), a.xsize() * sizeof(T)) != 0) return false;
  return true;
}

// Every radiance value and variance finite and >= 0, visibility in [0, 1], depth > 0 or +inf.
void CheckWellFormed(const ReferenceOutputs& out) {
  size_t bad = 0;
  for (size_t y = 0; y < out.depth.ysize(); ++y) {
    for (size_t x = 0; x < out.depth.xsize(); ++x) {
      for (const Plane3<float>* p : {&out.direct, &out.indirect, &out.result, &out.resultVariance})
        for (int c = 0; c < 3; ++c) {
          const float v = p->c[c].ConstRow(y)[x];
          if (!(std::isfinite(v) && v >= 0.0f)) ++bad;
        }
      const float visibility = out.lightVisibility.ConstRow(y)[x];
      if (!(visibility >= 0.0f && visibility <= 1.0f)) ++bad;
      const float depth = out.depth.ConstRow(y)[x];
      if (!(depth > 0.0f)) ++bad;
    }
  }
  CHECK(bad == 0);
}

TEST_CASE("reference primary visibility matches the rasterizer", "[reference]") {
  const TestScene scene = FeatureScene(160, 120);
  const ViewProjection view = MakePerspective(scene.camera, 160, 120);
  GBufferOutputs g;
  RunGBuffer({scene, view}, GBufferParams{}, g);
  ReferenceParams params;
  params.transport = ReferenceTransport::kPaper;
  params.lightSamples = 1;
  params.bounceSamples = 0;
  const ReferenceOutputs ref = RenderReferenceOf(scene, params);

  size_t agree = 0, background = 0, depthAgree = 0, bothCovered = 0, cutOut = 0, away = 0;
  for (int y = 0; y < 120; ++y) {
    for (int x = 0; x < 160; ++x) {
      const uint32_t triangle = g.visibility.triangle.ConstRow(y)[x];
      if (triangle != kNoTriangle) {
        cutOut += scene.mesh.materials[triangle] == kCutOutMaterial;
        away += scene.mesh.materials[triangle] == kAwayMaterial;
      }
      const float raster = UnpackDepth(g.gbuffer.word[GBufferWord::kDepth].ConstRow(y)[x]);
      const float traced = ref.depth.ConstRow(y)[x];
      if (IsBackground(raster) == IsBackground(traced)) ++agree;
      if (IsBackground(traced)) ++background;
      if (!IsBackground(raster) && !IsBackground(traced)) {
        ++bothCovered;
        if (std::fabs(raster - traced) <= 1e-3f * traced) ++depthAgree;
      }
    }
  }
  const double agreeing = double(agree) / (160.0 * 120.0);
  const double depthAgreeing = double(depthAgree) / double(bothCovered);
  WARN("background mask agreement " << agreeing << ", depth within 0.1 % on " << depthAgreeing
                                    << " of pixels covered in both; " << background << " background pixels");
  // The scene exercises what the comparison is about: sky, a cut-out surface, culled back faces.
  REQUIRE(background > 1000);
  REQUIRE(cutOut > 200);
  REQUIRE(away == 0);
  CHECK(agreeing >= 0.99);
  CHECK(depthAgreeing >= 0.98);  // differs only where a silhouette or cut-out edge falls between them
  CHECK(ref.stats.coveredPixels == 160 * 120 - background);
}

TEST_CASE("reference direct light on an open plane is the analytic BRDF value", "[reference]") {
  TestScene scene = MakeScene(Camera({0.0f, 3.0f, 3.0f}, {0.0f, 0.0f, 0.0f}, 40.0f), 48, 36);
  scene.materials[0].baseColor = glm::vec3(0.8f, 0.5f, 0.3f);
  scene.materials[0].roughness = 1.0f;
  AddGround(scene.mesh, 50.0f);
  ReferenceParams params;
  params.transport = ReferenceTransport::kPaper;
  params.lightSamples = 16;
  params.bounceSamples = 4;
  const SurfaceMaterial material{scene.materials[0].baseColor, 0.0f, 1.0f};
  const glm::vec3 up(0.0f, 1.0f, 0.0f);

  const auto check = [&](const TestScene& s, const auto& expectedAt) {
    const ReferenceOutputs out = RenderReferenceOf(s, params);
    const ViewProjection view = MakePerspective(s.camera, 48, 36);
    const glm::mat4 viewToWorld = glm::inverse(view.view);
    double worst = 0.0;
    size_t pixels = 0;
    for (int y = 0; y < 36; ++y) {
      for (int x = 0; x < 48; ++x) {
        const float depth = out.depth.ConstRow(y)[x];
        if (IsBackground(depth)) continue;
        const glm::vec3 p(viewToWorld * glm::vec4(view.PixelRay(x + 0.5f, y + 0.5f).direction * depth, 1.0f));
        const glm::vec3 expected = expectedAt(p, glm::normalize(s.camera.position - p));
        for (int c = 0; c < 3; ++c) {
          worst = std::max(worst, std::fabs(double(out.direct.c[c].ConstRow(y)[x]) / expected[c] - 1.0));
          // Nothing to reflect and a black sky: the bounce adds nothing.
          CHECK(out.indirect.c[c].ConstRow(y)[x] == 0.0f);
        }
        CHECK(out.lightVisibility.ConstRow(y)[x] == 1.0f);
        ++pixels;
      }
    }
    WARN("largest relative error of the direct light " << worst << " over " << pixels << " pixels");
    REQUIRE(pixels > 48 * 36 / 2);
    CHECK(worst < 0.02);
  };

  SECTION("sun 3 degrees wide, 35 degrees from the normal") {
    const DirectionalLight sun = Sun(LightDirection(35.0f, 60.0f), 3.0f);
    scene.directionalLights.push_back(sun);
    check(scene, [&](glm::vec3, glm::vec3 toViewer) {
      return BrdfCosine(material, 1.0f, up, toViewer, -sun.direction) * sun.irradiance;
    });
  }
  SECTION("spot light 2 m above the plane, 5 cm emitter") {
    SpotLight spot;
    spot.position = {0.0f, 2.0f, 0.0f};
    spot.direction = {0.0f, -1.0f, 0.0f};
    spot.innerConeDegrees = 75.0f;
    spot.outerConeDegrees = 85.0f;
    spot.radius = 0.05f;
    scene.spotLights.push_back(spot);
    // Within the inner cone: I / d^2 (a disc differs by r^2 / d^2 < 0.1 %).
    check(scene, [&](glm::vec3 p, glm::vec3 toViewer) {
      const glm::vec3 toLight = spot.position - p;
      const float d2 = glm::dot(toLight, toLight);
      return BrdfCosine(material, 1.0f, up, toViewer, toLight / std::sqrt(d2)) * spot.intensity / d2;
    });
  }
}

TEST_CASE("reference soft shadow of a floating slab", "[reference]") {
  // A sun straight down, 10 degrees wide, over a 1 m x 2 cm slab floating 0.5 m above the ground:
  // umbra under its centre, penumbra 0.5 +- 0.52 tan(5 deg) = 0.5 +- 0.045 from its centre line
  // (the outer boundary from its top edge, the inner from its bottom edge). The camera looks under
  // the slab from just below it.
  TestScene scene = MakeScene(Camera({0.0f, 0.45f, 1.6f}, {0.0f, 0.0f, 0.0f}, 50.0f), 96, 72);
  AddGround(scene.mesh, 4.0f);
  AddBox(scene.mesh, {-0.5f, 0.5f, -0.5f}, {0.5f, 0.52f, 0.5f});
  scene.directionalLights.push_back(Sun({0.0f, -1.0f, 0.0f}, 10.0f));
  ReferenceParams params;
  params.transport = ReferenceTransport::kPaper;
  params.lightSamples = 32;
  params.bounceSamples = 0;
  const ReferenceOutputs out = RenderReferenceOf(scene, params);
  const ViewProjection view = MakePerspective(scene.camera, 96, 72);
  const glm::mat4 viewToWorld = glm::inverse(view.view);

  size_t umbra = 0, umbraDark = 0, lit = 0, litBright = 0, penumbra = 0;
  for (int y = 0; y < 72; ++y) {
    for (int x = 0; x < 96; ++x) {
      const float depth = out.depth.ConstRow(y)[x];
      if (IsBackground(depth)) continue;
      const glm::vec3 p(viewToWorld * glm::vec4(view.PixelRay(x + 0.5f, y + 0.5f).direction * depth, 1.0f));
      if (std::fabs(p.y) > 1e-3f) continue;  // the ground only
      const float visibility = out.lightVisibility.ConstRow(y)[x];
      const float edge = std::max(std::fabs(p.x), std::fabs(p.z));  // 0.5 under the slab's sides
      if (edge < 0.35f) {
        ++umbra;
        umbraDark += visibility == 0.0f;
      } else if (edge > 0.7f) {
        ++lit;
        litBright += visibility == 1.0f;
      }
      if (visibility > 0.0f && visibility < 1.0f) {
        ++penumbra;
        CHECK(std::fabs(edge - 0.5f) < 0.05f);  // only within the penumbra's half-width (+ margin)
      }
    }
  }
  WARN(umbra << " umbra pixels, " << lit << " lit pixels, " << penumbra << " penumbra pixels");
  REQUIRE(umbra > 20);
  REQUIRE(lit > 100);
  CHECK(umbraDark == umbra);
  CHECK(litBright == lit);
  CHECK(penumbra > 10);
}

TestScene ConvergenceScene() {
  TestScene scene = MakeScene(Camera({0.5f, 1.8f, 3.0f}, {0.0f, 0.3f, 0.0f}, 45.0f), 32, 24);
  scene.materials[0].roughness = 0.5f;
  AddGround(scene.mesh, 3.0f);
  Mesh box;
  AddBox(box, {-0.9f, 0.0f, -0.5f}, {-0.2f, 0.7f, 0.2f});
  Append(scene.mesh, box, AddMaterial(scene, {0.95f, 0.64f, 0.54f}, 1.0f, 0.3f, false));
  Append(scene.mesh, Translated(MakeTorusKnot(64, 8), {0.5f, 0.5f, 0.0f}, 0.3f),
         AddMaterial(scene, {0.8f, 0.2f, 0.1f}, 0.0f, 0.4f, false));
  scene.directionalLights.push_back(Sun(LightDirection(45.0f, 20.0f), 8.0f));
  scene.background = {0.2f, 0.25f, 0.3f};
  return scene;
}

TEST_CASE("reference error falls as 1/sqrt(samples)", "[reference]") {
  const TestScene scene = ConvergenceScene();
  ReferenceParams truthParams = ReferenceParamsForSpp(1024, ReferenceTransport::kPaper);
  truthParams.seed = 1000;  // independent of the streams below
  const ReferenceOutputs truth = RenderReferenceOf(scene, truthParams);
  // The mean squared error over a few independent renders: one render's error is dominated by its
  // few brightest samples and would make the ratio itself noisy.
  constexpr int kRenders = 4;
  std::vector<double> rmse;
  for (int spp : {4, 16, 64}) {
    double meanSquared = 0.0;
    for (int i = 0; i < kRenders; ++i) {
      ReferenceParams params = ReferenceParamsForSpp(spp, ReferenceTransport::kPaper);
      params.seed = uint32_t(spp * kRenders + i);
      const double e = Rmse(RenderReferenceOf(scene, params).result, truth.result);
      meanSquared += e * e / kRenders;
    }
    rmse.push_back(std::sqrt(meanSquared));
  }
  // Against a 1024-spp truth the expected ratio is sqrt((1/4 + 1/1024) / (1/64 + 1/1024)) = 3.9.
  const double ratio = rmse[0] / rmse[2];
  WARN("RMSE at 4 / 16 / 64 spp: " << rmse[0] << " / " << rmse[1] << " / " << rmse[2] << ", 4-to-64 ratio "
                                   << ratio);
  CHECK(rmse[0] > rmse[1]);
  CHECK(rmse[1] > rmse[2]);
  CHECK(ratio > 2.5);
  CHECK(ratio < 6.0);
}

TEST_CASE("reference output is identical at 1, 2 and 3 threads", "[reference]") {
  TestScene scene = FeatureScene(67, 45);
  ReferenceParams params = ReferenceParamsForSpp(4, ReferenceTransport::kPaper);
  params.seed = 7;
  std::vector<ReferenceOutputs> outs;
  for (int threads : {1, 2, 3}) {
    const ThreadLimit limit(threads);
    size_t calls = 0, lastRows = 0;
    bool increasing = true;
    outs.push_back(RenderReferenceOf(scene, params, [&](size_t rowsDone, size_t rows) {
      increasing = increasing && rowsDone > lastRows && rows == 45;
      lastRows = rowsDone;
      ++calls;
    }));
    CHECK(increasing);
    CHECK(lastRows == 45);
    CHECK(calls == RowBandCount(45));
  }
  for (size_t i = 1; i < outs.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      CHECK(SameBytes(outs[0].direct.c[c], outs[i].direct.c[c]));
      CHECK(SameBytes(outs[0].indirect.c[c], outs[i].indirect.c[c]));
      CHECK(SameBytes(outs[0].result.c[c], outs[i].result.c[c]));
    }
    CHECK(SameBytes(outs[0].lightVisibility, outs[i].lightVisibility));
    CHECK(SameBytes(outs[0].depth, outs[i].depth));
    CHECK(outs[0].stats.rays == outs[i].stats.rays);
  }
  CheckWellFormed(outs[0]);
}

TEST_CASE("reference output is finite in degenerate set-ups", "[reference]") {
  const ReferenceTransport transport = GENERATE(ReferenceTransport::kPaper, ReferenceTransport::kFull);
  CAPTURE(int(transport));
  ReferenceParams params = ReferenceParamsForSpp(4, transport);
  SECTION("grazing sun, point-sized spot inside the geometry, mirrors") {
    TestScene scene = FeatureScene(40, 30);
    scene.materials[0].roughness = 0.0f;  // mirror ground
    scene.materials[0].metallic = 1.0f;
    scene.directionalLights[0] = Sun(LightDirection(89.99f, 10.0f), 0.0f);
    scene.directionalLights.push_back(Sun({0.0f, 1.0f, 0.0f}, 1.0f));  // from below the ground
    scene.spotLights[0].radius = 0.0f;
    scene.spotLights[0].position = {-1.0f, 0.4f, -0.2f};  // inside the box
    SpotLight onSurface;
    onSurface.position = {0.0f, 0.0f, 0.0f};  // on the ground, emitter crossing it
    onSurface.direction = {0.0f, 1.0f, 0.0f};
    onSurface.outerConeDegrees = 89.0f;
    scene.spotLights.push_back(onSurface);
    const ReferenceOutputs out = RenderReferenceOf(scene, params);
    CheckWellFormed(out);
  }
  SECTION("no lights, no geometry") {
    TestScene scene = MakeScene(Camera({0.0f, 1.0f, 3.0f}, {0.0f, 0.0f, 0.0f}, 45.0f), 9, 7);
    scene.background = {0.1f, 0.2f, 0.3f};
    const ReferenceOutputs out = RenderReferenceOf(scene, params);
    CheckWellFormed(out);
    CHECK(out.direct.c[2].ConstRow(3)[4] == 0.3f);
    CHECK(out.result.c[2].ConstRow(3)[4] == 0.3f);
    CHECK(out.stats.coveredPixels == 0);
  }
  SECTION("1x1 image, roughness 0 everywhere, camera inside a box") {
    TestScene scene = MakeScene(Camera({0.0f, 0.5f, 0.0f}, {0.0f, 0.5f, -1.0f}, 90.0f), 1, 1);
    scene.materials[0].roughness = 0.0f;
    AddBox(scene.mesh, {-1.0f, 0.0f, -1.0f}, {1.0f, 1.0f, 1.0f});
    scene.spotLights.push_back(SpotLight{});
    const ReferenceOutputs out = RenderReferenceOf(scene, params);
    CheckWellFormed(out);
    CHECK(out.stats.coveredPixels == 1);  // two-sided: the inside of the box is visible
  }
}

// A wavy 12 x 12 quad grid as OBJ text, without normals; `flipped` winds every other triangle the
// other way round, as real scenes' hand-edited meshes do.
std::string WavyGridObj(bool flipped, float scale = 1.0f) {
  constexpr int kCells = 12;
  std::string obj;
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i) {
      const float x = -1.0f + 2.0f * float(i) / kCells, z = -1.0f + 2.0f * float(j) / kCells;
      char line[96];
      std::snprintf(line, sizeof(line), "v %.9g %.9g %.9g\n", double(scale * x),
                    double(scale * 0.15f * std::sin(3.0f * x) * std::cos(2.0f * z)), double(scale * z));
      obj += line;
    }
  auto index = [](int i, int j) { return std::to_string(j * (kCells + 1) + i + 1); };
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      const std::string a = index(i, j), b = index(i, j + 1), c = index(i + 1, j + 1), d = index(i + 1, j);
      const bool flip = flipped && (i + j) % 2 == 1;
      obj += "f " + a + " " + (flip ? c + " " + b : b + " " + c) + "\n";  // up-facing: a b c, a c d
      obj += "f " + a + " " + c + " " + d + "\n";
    }
  return obj;
}

TEST_CASE("an inconsistently wound OBJ renders like the consistent one in both the rasterizer and the reference",
          "[reference][obj]") {
  test::ScratchDir dir("reference-winding");
  test::WriteText(dir / "consistent.obj", WavyGridObj(false));
  test::WriteText(dir / "flipped.obj", WavyGridObj(true));
  struct Rendered {
    GBufferOutputs g;
    ReferenceOutputs reference;
  };
  auto render = [&](const char* name) {
    TestScene scene = Sized(LoadScene(dir / name), 160, 120);
    Rendered r;
    RunGBuffer({scene, MakePerspective(scene.camera, 160, 120)}, GBufferParams{}, r.g);
    ReferenceParams params;
    params.transport = ReferenceTransport::kPaper;
    params.lightSamples = 4;
    params.bounceSamples = 0;
    r.reference = RenderReferenceOf(scene, params);
    return r;
  };
  const Rendered consistent = render("consistent.obj");
  const Rendered flipped = render("flipped.obj");
  size_t covered = 0, coverageMismatch = 0, normalMismatch = 0, radianceMismatch = 0;
  for (int y = 0; y < 120; ++y) {
    for (int x = 0; x < 160; ++x) {
      const bool a = !IsBackground(UnpackDepth(consistent.g.gbuffer.word[GBufferWord::kDepth].ConstRow(y)[x]));
      const bool b = !IsBackground(UnpackDepth(flipped.g.gbuffer.word[GBufferWord::kDepth].ConstRow(y)[x]));
      const bool ta = !IsBackground(consistent.reference.depth.ConstRow(y)[x]);
      const bool tb = !IsBackground(flipped.reference.depth.ConstRow(y)[x]);
      coverageMismatch += a != b || ta != tb;
      if (!a || !b) continue;
      ++covered;
      const glm::vec3 na = DecodeNormal(
          consistent.g.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(y)[x] & 0xFFFFFFu, NormalEncoding::kOct24);
      const glm::vec3 nb = DecodeNormal(
          flipped.g.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(y)[x] & 0xFFFFFFu, NormalEncoding::kOct24);
      normalMismatch += glm::dot(na, nb) < std::cos(glm::radians(0.5f));
      for (int c = 0; c < 3; ++c) {
        const float ra = consistent.reference.result.c[c].ConstRow(y)[x];
        const float rb = flipped.reference.result.c[c].ConstRow(y)[x];
        radianceMismatch += std::fabs(ra - rb) > 1e-3f * std::max(ra, 1e-3f);
      }
    }
  }
  WARN("flipped-winding grid: " << covered << " covered pixels, " << coverageMismatch << " coverage, " << normalMismatch
                                << " normal and " << radianceMismatch << " reference radiance mismatches");
  REQUIRE(covered > 1000);
  CHECK(coverageMismatch == 0);  // no holes where back faces would have been culled
  CHECK(normalMismatch == 0);    // shading normals smooth across the flips, turned to the viewer
  CHECK(radianceMismatch == 0);
}

// The same surface in millimetres, metres and kilometres, each framed by the bare-OBJ camera: the
// screen-space frame (shadow-map fit, biases, blur and SSR thresholds, near plane are all relative)
// and the reference must give the same picture.
TEST_CASE("a scene renders the same at any scale, in the frame and in the reference", "[reference][obj]") {
  test::ScratchDir dir("reference-scale");
  struct Rendered {
    std::vector<uint8_t> display;
    ReferenceOutputs reference;
  };
  auto render = [&](float scale) {
    const std::string name = "grid_" + std::to_string(int(std::log10(scale))) + ".obj";
    test::WriteText(dir / name, WavyGridObj(false, scale));
    TestScene scene = Sized(LoadScene(dir / name), 160, 120);
    scene.materials[0].roughness = 0.2f;  // smooth enough to reflect: every pass runs
    Rendered r;
    const Frame frame = RenderFrame(scene, ConfigOf(scene));
    REQUIRE(frame.shadowMap);
    REQUIRE(frame.reflections);
    r.display = frame.display.rgb;
    ReferenceParams params;
    params.transport = ReferenceTransport::kPaper;
    params.lightSamples = 4;
    params.bounceSamples = 1;
    r.reference = RenderReferenceOf(scene, params);
    return r;
  };
  const Rendered metres = render(1.0f);
  for (const float scale : {1e-3f, 1e3f}) {
    CAPTURE(scale);
    const Rendered scaled = render(scale);
    REQUIRE(scaled.display.size() == metres.display.size());
    size_t displayOff = 0;
    for (size_t i = 0; i < metres.display.size(); ++i)
      displayOff += std::abs(int(scaled.display[i]) - int(metres.display[i])) > 2;
    size_t referenceOff = 0;
    for (int c = 0; c < 3; ++c)
      for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x) {
          const float a = metres.reference.result.c[c].ConstRow(y)[x];
          const float b = scaled.reference.result.c[c].ConstRow(y)[x];
          referenceOff += std::fabs(a - b) > 1e-2f * std::max(a, 1e-2f);
        }
    WARN("scale " << scale << ": " << displayOff << " display samples off by more than 2 codes, " << referenceOff
                  << " reference samples off by more than 1%, of " << metres.display.size());
    // Rounding at a different magnitude may move a silhouette or shadow edge by a pixel, no more.
    CHECK(displayOff <= metres.display.size() / 200);
    CHECK(referenceOff <= metres.display.size() / 200);
  }
}

// ---------------------------------------------------------------------------------------------------
// The full transport (ReferenceTransport::kFull): the path tracer against values derived here
// independently of it, and against the paper transport where the two must agree.

// A UV sphere of radius 1 around the origin, `segments` around y by `rings` from pole to pole,
// wound to face outward (or inward) and with normals equal to the positions (or their negatives):
// the interpolated normal at a point p of a facet is then parallel to p itself (sum w_i v_i = p),
// so a test knows the shading normal of every hit exactly.
Mesh UnitSphere(int segments, int rings, bool inward) {
  Mesh mesh;
  for (int i = 0; i <= rings; ++i) {
    const double theta = kPi * double(i) / rings;
    for (int j = 0; j <= segments; ++j) {
      const double phi = 2.0 * kPi * double(j) / segments;
      const glm::vec3 p(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                        float(std::sin(theta) * std::sin(phi)));
      mesh.positions.push_back(p);
      mesh.normals.push_back(inward ? -p : p);
      mesh.uvs.push_back({0.0f, 0.0f});
    }
  }
  const auto at = [&](int i, int j) { return uint32_t(i * (segments + 1) + j); };
  const auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
    const glm::vec3 &pa = mesh.positions[a], &pb = mesh.positions[b], &pc = mesh.positions[c];
    const bool outward = glm::dot(glm::cross(pb - pa, pc - pa), pa + pb + pc) > 0.0f;
    if (outward != inward) {
      mesh.indices.insert(mesh.indices.end(), {a, b, c});
    } else {
      mesh.indices.insert(mesh.indices.end(), {a, c, b});
    }
    mesh.materials.push_back(0);
  };
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      if (i > 0) add(at(i, j), at(i + 1, j), at(i, j + 1));                  // none at the top pole
      if (i < rings - 1) add(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));  // none at the bottom pole
    }
  }
  return mesh;
}

// The full transport of a test scene, one path per pixel centre unless `jitter`.
ReferenceOutputs RenderFull(const TestScene& scene, int spp, int bounces, uint32_t seed, bool jitter = false) {
  ReferenceParams params = ReferenceParamsForSpp(spp);
  params.bounces = bounces;
  params.pixelCentre = !jitter;
  params.seed = seed;
  return RenderReferenceOf(scene, params);
}

// The world position of the pixel-centre hit of pixel (x, y), from the reference's depth.
glm::vec3 HitPosition(const ViewProjection& view, const glm::mat4& viewToWorld, int x, int y, float depth) {
  return glm::vec3(viewToWorld * glm::vec4(view.PixelRay(x + 0.5f, y + 0.5f).direction * depth, 1.0f));
}

// (A, B) of the specular lobe as core/brdf.h writes it, at n.v and GGX alpha: the hemispherical
// integrals of D V n.l (1 - Fc) and D V n.l Fc, Fc = (1 - v.h)^5, so that the lobe's directional
// albedo is F0 A + B. A product midpoint rule over the light direction l = (mu, phi): mu = t^2
// with t uniform (nodes gathered towards the horizon, where a grazing viewer's lobe lies), phi
// uniform over [0, pi] (the integrand is even in it), enough nodes in phi for a lobe that narrows
// at grazing angles (converged to 1e-5 at n.v = 1/31 and roughness 0.5). Independent of the
// shipped table (1024 Hammersley half vectors per entry, rescaled where A + B > 1).
glm::dvec2 SpecularAlbedoByQuadrature(double nDotV, double alpha) {
  constexpr int kT = 96, kPhi = 384;
  const double a2 = alpha * alpha;
  const glm::dvec3 v(std::sqrt(std::max(0.0, 1.0 - nDotV * nDotV)), 0.0, nDotV);
  const double lambdaV = std::sqrt(a2 + (1.0 - a2) * nDotV * nDotV);
  double a = 0.0, b = 0.0;
  for (int i = 0; i < kT; ++i) {
    const double t = (i + 0.5) / kT;
    const double mu = t * t, dMu = 2.0 * t / kT;
    const double sinL = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    const double lambdaL = std::sqrt(a2 + (1.0 - a2) * mu * mu);
    const double visibility = 0.5 / (mu * lambdaV + nDotV * lambdaL);
    for (int k = 0; k < kPhi; ++k) {
      const double phi = double(kPi) * (k + 0.5) / kPhi;
      const glm::dvec3 h = glm::normalize(v + glm::dvec3(sinL * std::cos(phi), sinL * std::sin(phi), mu));
      const double f = h.z * h.z * (a2 - 1.0) + 1.0;
      const double d = a2 / (double(kPi) * f * f);
      const double weight = d * visibility * mu * dMu * (2.0 * double(kPi) / kPhi);
      const double fc = std::pow(1.0 - glm::dot(v, h), 5.0);
      a += (1.0 - fc) * weight;
      b += fc * weight;
    }
  }
  return {a, b};
}

// The furnace: a sphere inside a uniform environment of radiance L. A sphere is convex, so every
// direction above its surface sees the environment and nothing else (single scattering), and the
// radiance it sends towards the camera is L times the BRDF's directional albedo at that pixel's
// n.v: for core/brdf.h's BRDF (Lambert rho (1 - m) / pi, not weighted by 1 - F, plus the GGX lobe)
// L (rho (1 - m) + F0 A + B), F0 = mix(0.04, rho, m), per channel.
struct FurnaceCheck {
  size_t pixels = 0, outliers = 0;
  double meanError = 0.0, meanSigma = 0.0, meanExpected = 0.0;  // relative sums over pixels
  double worstZ = 0.0;
};

template <class Expected>
FurnaceCheck CheckFurnace(const TestScene& scene, const ReferenceOutputs& out, const Expected& expectedAt,
                          double systematic) {
  const ViewProjection view = MakePerspective(scene.camera, scene.width, scene.height);
  const glm::mat4 viewToWorld = glm::inverse(view.view);
  FurnaceCheck check;
  double sumError = 0.0, sumVariance = 0.0, sumExpected = 0.0, sumSigma = 0.0;
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
      const float depth = out.depth.ConstRow(y)[x];
      if (IsBackground(depth)) continue;
      const glm::vec3 p = HitPosition(view, viewToWorld, x, y, depth);
      const glm::dvec3 n = glm::normalize(glm::dvec3(p));
      const double nDotV = glm::dot(n, glm::normalize(glm::dvec3(scene.camera.position) - glm::dvec3(p)));
      if (nDotV < 1e-3) continue;  // the silhouette: shading and test normals may disagree in sign
      const glm::dvec3 expected = expectedAt(nDotV);
      ++check.pixels;
      bool outlier = false;
      for (int c = 0; c < 3; ++c) {
        const double value = out.result.c[c].ConstRow(y)[x];
        const double sigma = std::sqrt(double(out.resultVariance.c[c].ConstRow(y)[x]));
        const double error = value - expected[c];
        sumError += error;
        sumVariance += sigma * sigma;
        sumExpected += expected[c];
        sumSigma += sigma;
        check.worstZ = std::max(check.worstZ, std::fabs(error) / std::max(sigma, 1e-12));
        outlier = outlier || std::fabs(error) > 5.0 * sigma + systematic * expected[c];
      }
      check.outliers += outlier;
    }
  }
  check.meanError = sumError / sumExpected;
  check.meanSigma = sumSigma / sumExpected;
  check.meanExpected = sumExpected / double(3 * check.pixels);
  // The mean error's own standard error, relative: independent pixels, so variances add.
  const double meanSigma = std::sqrt(sumVariance) / sumExpected;
  WARN(check.pixels << " pixels: mean relative error " << check.meanError << " (standard error " << meanSigma
                    << "), mean relative sigma per pixel " << check.meanSigma << ", largest |error| / sigma "
                    << check.worstZ << ", " << check.outliers << " pixels beyond 5 sigma + " << systematic);
  CHECK(std::fabs(check.meanError) < 5.0 * meanSigma + systematic);
  return check;
}

TestScene FurnaceScene(const SurfaceMaterial& material, glm::vec3 environment) {
  TestScene scene = MakeScene(Camera({0.0f, 0.0f, 3.2f}, {0.0f, 0.0f, 0.0f}, 45.0f), 40, 40);
  scene.materials[0] = Material{};
  scene.materials[0].baseColor = material.albedo;
  scene.materials[0].metallic = material.metallic;
  scene.materials[0].roughness = material.roughness;
  scene.mesh = UnitSphere(256, 128, false);
  scene.background = environment;
  return scene;
}

// Facets: the shading normal is the sphere's, the facet is not, so a few directions near the
// horizon leave below the facet's plane and see the sphere's inside (the terminator effect of a
// coarse mesh); 256 x 128 facets keep it below this share of the radiance.
constexpr double kFacetAllowance = 2e-3;

TEST_CASE("reference full transport: a furnace sphere renders L (rho (1 - m) + F0 A + B)", "[reference]") {
  const SurfaceMaterial material{{0.8f, 0.5f, 0.2f}, 0.3f, 0.5f};
  const glm::vec3 environment(1.0f, 0.8f, 1.2f);
  const TestScene scene = FurnaceScene(material, environment);
  const ReferenceOutputs out = RenderFull(scene, 512, kDefaultReferenceBounces, 11);
  const float alpha = std::max(material.roughness * material.roughness, kMinGgxAlpha);
  const glm::dvec3 f0 = glm::dvec3(SpecularF0(material));
  const FurnaceCheck check = CheckFurnace(
      scene, out,
      [&](double nDotV) {
        const glm::dvec2 ab = SpecularAlbedoByQuadrature(nDotV, alpha);
        return glm::dvec3(environment) *
               (glm::dvec3(material.albedo) * (1.0 - double(material.metallic)) + f0 * ab.x + ab.y);
      },
      kFacetAllowance);
  REQUIRE(check.pixels > 600);
  CHECK(check.outliers == 0);
  CHECK(check.meanSigma < 0.03);  // the per-pixel test has teeth: 5 sigma is a few percent
}

TEST_CASE("reference full transport: a metal furnace sphere renders A + B, the DFG table's", "[reference]") {
  // F0 = 1: Fresnel is 1, the lobe's albedo A + B. Roughness on a table row, so the table
  // interpolates in n.v only.
  constexpr int kRow = 16;
  const SurfaceMaterial material{{1.0f, 1.0f, 1.0f}, 1.0f, float(kRow) / (kDfgSize - 1)};
  const TestScene scene = FurnaceScene(material, glm::vec3(1.0f));
  const ReferenceOutputs out = RenderFull(scene, 256, kDefaultReferenceBounces, 12);
  const float alpha = std::max(material.roughness * material.roughness, kMinGgxAlpha);
  const DfgTable& table = ShippedDfgTable();
  const auto node = [&](int i) {
    const glm::vec2 ab = table.ab[size_t(kRow * kDfgSize + std::clamp(i, 0, kDfgSize - 1))];
    return double(ab.x) + double(ab.y);
  };
  // The table's own error at its nodes (1024 Hammersley samples each), against the quadrature: it
  // grows towards grazing angles, where the lobe narrows.
  std::vector<double> nodeError(kDfgSize, 0.0);
  for (int i = 1; i < kDfgSize; ++i) {
    const glm::dvec2 ab = SpecularAlbedoByQuadrature(double(i) / (kDfgSize - 1), alpha);
    nodeError[size_t(i)] = std::fabs(node(i) - (ab.x + ab.y));
  }
  WARN("DFG table row " << kRow << ": error at its nodes n.v = 1/31, 2/31, 4/31, 8/31, 16/31, 1: " << nodeError[1]
                        << ", " << nodeError[2] << ", " << nodeError[4] << ", " << nodeError[8] << ", " << nodeError[16]
                        << ", " << nodeError[31]);
  // The quadrature and the table agree to their errors: each is what the other says it is.
  CHECK(*std::max_element(nodeError.begin(), nodeError.end()) < 0.03);
  // Against the table: its bilinear interpolation errs by at most h^2 / 8 |f''|, estimated by the
  // larger second difference of the cell's neighbourhood over 8, plus its node error.
  const ViewProjection view = MakePerspective(scene.camera, scene.width, scene.height);
  const glm::mat4 viewToWorld = glm::inverse(view.view);
  size_t pixels = 0, outliers = 0;
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
      const float depth = out.depth.ConstRow(y)[x];
      if (IsBackground(depth)) continue;
      const glm::vec3 p = HitPosition(view, viewToWorld, x, y, depth);
      const float nDotV = glm::dot(glm::normalize(p), glm::normalize(scene.camera.position - p));
      if (nDotV < 1e-3f) continue;
      const int i = std::min(int(nDotV * (kDfgSize - 1)), kDfgSize - 2);
      const double secondDifference = std::max(std::fabs(node(i - 1) - 2.0 * node(i) + node(i + 1)),
                                               std::fabs(node(i) - 2.0 * node(i + 1) + node(i + 2)));
      // Row 0 (n.v = 0) is integrated at n.v = 1e-4 and rescaled: its error is the next node's bound.
      const double tolerance =
          secondDifference / 8.0 + std::max(nodeError[size_t(std::max(i, 1))], nodeError[size_t(i + 1)]);
      const double expected = SpecularWeight(glm::vec3(1.0f), nDotV, material.roughness).x;
      const double value = out.result.c[1].ConstRow(y)[x];
      const double sigma = std::sqrt(double(out.resultVariance.c[1].ConstRow(y)[x]));
      ++pixels;
      outliers += std::fabs(value - expected) > 5.0 * sigma + tolerance + kFacetAllowance * expected;
    }
  }
  WARN(pixels << " pixels, " << outliers << " beyond 5 sigma + the table's interpolation error");
  REQUIRE(pixels > 600);
  CHECK(outliers == 0);
  // And against the quadrature, as the furnace above.
  const FurnaceCheck check = CheckFurnace(
      scene, out,
      [&](double nDotV) {
        const glm::dvec2 ab = SpecularAlbedoByQuadrature(nDotV, alpha);
        return glm::dvec3(ab.x + ab.y);
      },
      kFacetAllowance);
  CHECK(check.outliers == 0);
  CHECK(check.meanSigma < 0.03);
}

// The radiance field inside a sphere whose wall receives the same irradiance E at normal incidence
// everywhere. The chord between two wall points makes the same angle with both normals, so the
// radiance leaving every point depends only on mu, the cosine of its direction with the normal,
// and the light arriving at a point from direction mu is the light leaving the far point at mu:
//   L1(mu_o) = f(mu_o, normal) E                      (the first reflection: the direct light)
//   L(mu_o) = L1 + Integral f(mu_o, w_i) L(mu_i) mu_i dw_i.
// The indirect part L - L1, by the Neumann series over a midpoint rule in mu_i and the relative
// azimuth (the integrand even in it). `brdfCosine(v, l)` is f times n.l with n = +z. For a
// Lambertian f = rho / pi it is rho E / pi * rho / (1 - rho): the classic integrating sphere's
// rho / pi * E_indirect, E_indirect = Phi rho / (4 pi R^2 (1 - rho)) with E = Phi / (4 pi R^2).
class SphereInterreflection {
 public:
  using BrdfCosineFn = std::function<double(const glm::vec3& v, const glm::vec3& l)>;
  SphereInterreflection(const BrdfCosineFn& brdfCosine, double irradiance) : brdfCosine_(brdfCosine) {
    std::vector<double> direct(kMu);
    for (int j = 0; j < kMu; ++j) direct[j] = brdfCosine_(Direction(Mu(j), 0.0), {0.0f, 0.0f, 1.0f}) * irradiance;
    std::vector<std::vector<double>> kernel(kMu);
    for (int i = 0; i < kMu; ++i) kernel[i] = KernelRow(Mu(i));
    indirect_.assign(kMu, 0.0);
    for (int iteration = 0; iteration < 200; ++iteration) {
      std::vector<double> next(kMu, 0.0);
      for (int i = 0; i < kMu; ++i)
        for (int j = 0; j < kMu; ++j) next[i] += kernel[i][j] * (direct[j] + indirect_[j]);
      indirect_ = next;
    }
    total_.resize(kMu);
    for (int j = 0; j < kMu; ++j) total_[j] = direct[j] + indirect_[j];
  }
  // L - L1 leaving the wall at cosine muOut (Nystrom: the kernel row at muOut).
  double Indirect(double muOut) const {
    const std::vector<double> row = KernelRow(muOut);
    double sum = 0.0;
    for (int j = 0; j < kMu; ++j) sum += row[j] * total_[j];
    return sum;
  }

 private:
  static constexpr int kMu = 192, kPhi = 48;
  static double Mu(int j) { return (j + 0.5) / kMu; }
  static glm::vec3 Direction(double mu, double phi) {
    const double s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    return glm::vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(mu));
  }
  // Weights of L(mu_j) in the integral at muOut: f mu_j dmu dphi over mu_j's cell, phi in [0, 2 pi).
  std::vector<double> KernelRow(double muOut) const {
    std::vector<double> row(kMu, 0.0);
    const glm::vec3 v = Direction(muOut, 0.0);
    for (int j = 0; j < kMu; ++j) {
      double sum = 0.0;
      for (int k = 0; k < kPhi; ++k) sum += brdfCosine_(v, Direction(Mu(j), kPi * (k + 0.5) / kPhi));
      row[j] = sum * (2.0 * kPi / kPhi) / kMu;
    }
    return row;
  }
  BrdfCosineFn brdfCosine_;
  std::vector<double> indirect_, total_;
};

TEST_CASE("reference full transport: an integrating sphere holds the interreflection of its wall", "[reference]") {
  // A closed sphere (radius 1, inward normals) of albedo rho and roughness 1, the most diffuse
  // core/brdf.h's BRDF gets, lit from its centre by two point spots back to back whose cones
  // (89.99 degrees, no falloff band to speak of) light the whole wall at normal incidence.
  const SurfaceMaterial material{{0.5f, 0.5f, 0.5f}, 0.0f, 1.0f};
  TestScene scene = MakeScene(Camera({0.0f, -0.3f, 0.4f}, {0.1f, 0.7f, -0.6f}, 60.0f), 40, 30);
  scene.materials[0] = Material{};
  scene.materials[0].baseColor = material.albedo;
  scene.materials[0].roughness = material.roughness;
  scene.mesh = UnitSphere(256, 128, true);
  for (const float y : {1.0f, -1.0f}) {
    SpotLight spot = test::Spot({0.0f, 0.0f, 0.0f}, {0.0f, y, 0.0f}, 89.99f, 0.0f);
    spot.innerConeDegrees = 89.99f;
    spot.intensity = glm::vec3(2.0f);
    scene.spotLights.push_back(spot);
  }
  // The spots' power by integrating their intensity I c(theta)^2 (core/lighting.h's cone) over
  // the sphere of directions: 2 pi I Integral c(mu)^2 dmu each, midpoint rule in mu = cos theta.
  double power = 0.0;
  for (const SpotLight& spot : scene.spotLights) {
    const PreparedLight light = Prepare(spot, glm::mat4(1.0f));
    constexpr int kNodes = 1 << 20;
    double integral = 0.0;
    for (int k = 0; k < kNodes; ++k) {
      const double mu = (k + 0.5) / kNodes;
      const double c = std::clamp((mu - double(light.cosOuter)) * double(light.coneScale), 0.0, 1.0);
      integral += c * c / kNodes;
    }
    power += 2.0 * double(kPi) * double(light.power.x) * integral;
  }
  const double irradiance = power / (4.0 * double(kPi));  // Phi / (4 pi R^2)
  WARN("spots' power " << power << " W, against 4 pi I = " << 4.0 * kPi * 2.0);

  const float alpha = std::max(material.roughness * material.roughness, kMinGgxAlpha);
  const SphereInterreflection sphere(
      [&](const glm::vec3& v, const glm::vec3& l) {
        return double(BrdfCosine(material, alpha, {0.0f, 0.0f, 1.0f}, v, l).x);
      },
      irradiance);
  // The solver itself against the classic closed form, for a Lambertian wall.
  const double rho = material.albedo.x;
  const SphereInterreflection lambertian(
      [&](const glm::vec3&, const glm::vec3& l) { return rho / kPi * std::max(0.0, double(l.z)); }, irradiance);
  const double classic = rho / kPi * power * rho / (4.0 * kPi * (1.0 - rho));
  CHECK(std::fabs(lambertian.Indirect(0.7) / classic - 1.0) < 1e-4);
  WARN("indirect radiance at mu = 0.7: " << sphere.Indirect(0.7) << " for the BRDF, " << classic
                                         << " for a Lambertian wall of the same albedo");

  const ReferenceOutputs out = RenderFull(scene, 256, 64, 21);
  const ViewProjection view = MakePerspective(scene.camera, scene.width, scene.height);
  const glm::mat4 viewToWorld = glm::inverse(view.view);
  struct WallPixel {
    double value, expected, variance;
  };
  std::vector<WallPixel> wall;
  size_t directOff = 0;
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
      const float depth = out.depth.ConstRow(y)[x];
      REQUIRE(!IsBackground(depth));  // closed: every ray meets the wall
      const glm::vec3 p = HitPosition(view, viewToWorld, x, y, depth);
      if (std::fabs(p.y) < 0.01f) continue;  // the cones' edge
      const glm::vec3 n = -glm::normalize(p);
      const glm::vec3 v = glm::normalize(scene.camera.position - p);
      // The direct light is a point light's: exact, no noise, so result's variance is indirect's.
      const double direct = double(BrdfCosine(material, alpha, n, v, n).x) * 2.0 / double(glm::dot(p, p));
      directOff += std::fabs(out.direct.c[0].ConstRow(y)[x] - direct) > 1e-4 * direct;
      wall.push_back({out.indirect.c[0].ConstRow(y)[x], sphere.Indirect(glm::dot(n, v)),
                      double(out.resultVariance.c[0].ConstRow(y)[x])});
    }
  }
  REQUIRE(wall.size() > 1000);
  CHECK(directOff == 0);
  double sumError = 0.0, sumVariance = 0.0, sumExpected = 0.0;
  for (const WallPixel& w : wall) {
    sumError += w.value - w.expected;
    sumVariance += w.variance;
    sumExpected += w.expected;
  }
  const double meanError = sumError / sumExpected, meanSigma = std::sqrt(sumVariance) / sumExpected;
  // Per pixel, against the larger of its own standard error and the wall's root mean one: a path's
  // light is skewed (rare long bright paths), so a pixel that drew few of them has both a low value
  // and a low sample variance; the wall's pixels all see the same sphere.
  const double pooledSigma = std::sqrt(sumVariance / double(wall.size()));
  size_t outliers = 0;
  for (const WallPixel& w : wall)
    outliers += std::fabs(w.value - w.expected) >
                5.0 * std::max(std::sqrt(w.variance), pooledSigma) + kFacetAllowance * w.expected;
  WARN(wall.size() << " wall pixels: mean relative error of the indirect light " << meanError << " (standard error "
                   << meanSigma << "), relative sigma per pixel " << pooledSigma * double(wall.size()) / sumExpected
                   << ", " << outliers << " beyond 5 sigma");
  CHECK(outliers == 0);
  CHECK(pooledSigma * double(wall.size()) / sumExpected < 0.05);
  CHECK(std::fabs(meanError) < 5.0 * meanSigma + kFacetAllowance);
}

// Boxes of copper and silver (metallic 1: no diffuse lobe) on a diffuse ground beside a red box,
// under a sun and a spot with a disc: the metals reflect diffuse surfaces lit by both.
constexpr glm::vec3 kCopperLo{-0.9f, 0.0f, -0.5f}, kCopperHi{-0.2f, 0.7f, 0.2f};
constexpr glm::vec3 kSilverLo{0.2f, 0.0f, -0.4f}, kSilverHi{0.8f, 0.5f, 0.1f};

TestScene AgreementScene() {
  TestScene scene = MakeScene(Camera({0.3f, 1.6f, 2.6f}, {0.0f, 0.3f, -0.1f}, 45.0f), 48, 36);
  scene.materials[0].baseColor = glm::vec3(0.7f);
  scene.materials[0].roughness = 0.6f;
  AddGround(scene.mesh, 3.0f);
  Mesh box;
  AddBox(box, kCopperLo, kCopperHi);
  Append(scene.mesh, box, AddMaterial(scene, {0.95f, 0.64f, 0.54f}, 1.0f, 0.3f, false));
  box = Mesh{};
  AddBox(box, kSilverLo, kSilverHi);
  Append(scene.mesh, box, AddMaterial(scene, {0.9f, 0.9f, 0.9f}, 1.0f, 0.15f, false));
  box = Mesh{};
  AddBox(box, {-0.15f, 0.0f, 0.3f}, {0.35f, 0.35f, 0.7f});
  Append(scene.mesh, box, AddMaterial(scene, {0.8f, 0.15f, 0.1f}, 0.0f, 0.5f, false));
  scene.directionalLights.push_back(Sun(LightDirection(40.0f, 60.0f), 8.0f));
  SpotLight spot = test::Spot({0.6f, 1.6f, 0.9f}, {-0.3f, -1.0f, -0.4f}, 50.0f, 0.2f);
  spot.intensity = glm::vec3(5.0f, 4.0f, 3.0f);
  scene.spotLights.push_back(spot);
  scene.background = glm::vec3(0.0f);  // black: the paper transport has no environment light
  return scene;
}

bool Inside(glm::vec3 p, glm::vec3 lo, glm::vec3 hi, float margin) {
  return p.x > lo.x - margin && p.x < hi.x + margin && p.y > lo.y - margin && p.y < hi.y + margin &&
         p.z > lo.z - margin && p.z < hi.z + margin;
}

TEST_CASE("reference full transport, one bounce, agrees with the paper transport where nothing is diffuse",
          "[reference]") {
  // With a black environment and one bounce the full transport is the paper transport's light
  // plus, at the first hit, the diffuse lobe's bounce. The two agree on every pixel's direct light,
  // and on the whole result of pixels whose pixel-centre ray first hits a metal box (metallic 1:
  // no diffuse lobe at the first hit; the second hit's direct light is the full BRDF's in both).
  const TestScene scene = AgreementScene();
  ReferenceParams truthParams = ReferenceParamsForSpp(1024, ReferenceTransport::kPaper);
  truthParams.seed = 1000;
  const ReferenceOutputs truth = RenderReferenceOf(scene, truthParams);
  const ViewProjection view = MakePerspective(scene.camera, scene.width, scene.height);
  const glm::mat4 viewToWorld = glm::inverse(view.view);
  std::vector<std::pair<int, int>> metal, covered;
  double truthIndirect = 0.0, truthResult = 0.0;
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
      const float depth = truth.depth.ConstRow(y)[x];
      if (IsBackground(depth)) continue;
      covered.push_back({x, y});
      const glm::vec3 p = HitPosition(view, viewToWorld, x, y, depth);
      if (p.y > 1e-3f && (Inside(p, kCopperLo, kCopperHi, 1e-3f) || Inside(p, kSilverLo, kSilverHi, 1e-3f))) {
        metal.push_back({x, y});
        truthIndirect += truth.indirect.c[1].ConstRow(y)[x];
        truthResult += truth.result.c[1].ConstRow(y)[x];
      }
    }
  }
  REQUIRE(metal.size() > 150);
  // The reflections are a real part of the metals' light: not an agreement of zeros.
  CHECK(truthIndirect > 0.1 * truthResult);
  const auto rmse = [](const Plane3<float>& a, const Plane3<float>& b, const std::vector<std::pair<int, int>>& at) {
    double sum = 0.0;
    for (const auto& [x, y] : at)
      for (int c = 0; c < 3; ++c) {
        const double d = double(a.c[c].ConstRow(y)[x]) - double(b.c[c].ConstRow(y)[x]);
        sum += d * d;
      }
    return std::sqrt(sum / double(3 * at.size()));
  };
  constexpr int kRenders = 4;
  std::vector<double> resultError, directError;
  for (int spp : {4, 16, 64}) {
    double result2 = 0.0, direct2 = 0.0;
    for (int i = 0; i < kRenders; ++i) {
      const ReferenceOutputs full = RenderFull(scene, spp, 1, uint32_t(spp * kRenders + i));
      result2 += std::pow(rmse(full.result, truth.result, metal), 2) / kRenders;
      direct2 += std::pow(rmse(full.direct, truth.direct, covered), 2) / kRenders;
    }
    resultError.push_back(std::sqrt(result2));
    directError.push_back(std::sqrt(direct2));
  }
  WARN("metal pixels' result RMSE at 4 / 16 / 64 spp: "
       << resultError[0] << " / " << resultError[1] << " / " << resultError[2]
       << "; every pixel's direct light: " << directError[0] << " / " << directError[1] << " / " << directError[2]);
  // Unbiased, against a 1024-spp truth: each 4x more samples halve the error (a bias would
  // flatten it).
  for (const std::vector<double>* e : {&resultError, &directError}) {
    CHECK((*e)[0] / (*e)[1] > 1.6);
    CHECK((*e)[1] / (*e)[2] > 1.6);
    CHECK((*e)[0] / (*e)[2] > 3.0);
    CHECK((*e)[0] / (*e)[2] < 5.5);
  }
}

TEST_CASE("reference full transport: identical at 1, 2 and 3 threads", "[reference]") {
  TestScene scene = FeatureScene(67, 45);
  ReferenceParams params = ReferenceParamsForSpp(4);
  params.seed = 7;
  std::vector<ReferenceOutputs> outs;
  for (int threads : {1, 2, 3}) {
    const ThreadLimit limit(threads);
    size_t calls = 0, lastRows = 0;
    bool increasing = true;
    outs.push_back(RenderReferenceOf(scene, params, [&](size_t rowsDone, size_t rows) {
      increasing = increasing && rowsDone > lastRows && rows == 45;
      lastRows = rowsDone;
      ++calls;
    }));
    CHECK(increasing);
    CHECK(lastRows == 45);
    CHECK(calls == RowBandCount(45));
  }
  for (size_t i = 1; i < outs.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      CHECK(SameBytes(outs[0].direct.c[c], outs[i].direct.c[c]));
      CHECK(SameBytes(outs[0].indirect.c[c], outs[i].indirect.c[c]));
      CHECK(SameBytes(outs[0].result.c[c], outs[i].result.c[c]));
      CHECK(SameBytes(outs[0].resultVariance.c[c], outs[i].resultVariance.c[c]));
    }
    CHECK(SameBytes(outs[0].lightVisibility, outs[i].lightVisibility));
    CHECK(SameBytes(outs[0].depth, outs[i].depth));
    CHECK(outs[0].stats.rays == outs[i].stats.rays);
  }
  CheckWellFormed(outs[0]);
  // The environment lights the scene: indirect light on surfaces the paper transport leaves at 0.
  double indirect = 0.0;
  for (int y = 0; y < 45; ++y)
    for (int x = 0; x < 67; ++x) indirect += outs[0].indirect.c[2].ConstRow(y)[x];
  CHECK(indirect > 0.0);
  CHECK(outs[0].stats.paths == size_t(67 * 45 * 4));
}

}  // namespace
}  // namespace ssgi
