// The Embree reference (core/reference/reference.h): primary visibility against the rasterizer, direct light
// against analytic values, area-light soft shadows, Monte Carlo convergence, determinism and
// finiteness in degenerate set-ups.
#include "core/reference/reference.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include <catch2/catch.hpp>

#include "core/brdf.h"
#include "core/gbuffer.h"
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
  params.environment = {EnvironmentKind::kConstant, scene.background};
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

// Every radiance value finite and >= 0, visibility in [0, 1], depth > 0 or +inf.
void CheckWellFormed(const ReferenceOutputs& out) {
  size_t bad = 0;
  for (size_t y = 0; y < out.depth.ysize(); ++y) {
    for (size_t x = 0; x < out.depth.xsize(); ++x) {
      for (const Plane3<float>* p : {&out.direct, &out.indirect, &out.result})
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
  ReferenceParams truthParams = ReferenceParamsForSpp(1024);
  truthParams.seed = 1000;  // independent of the streams below
  const ReferenceOutputs truth = RenderReferenceOf(scene, truthParams);
  // The mean squared error over a few independent renders: one render's error is dominated by its
  // few brightest samples and would make the ratio itself noisy.
  constexpr int kRenders = 4;
  std::vector<double> rmse;
  for (int spp : {4, 16, 64}) {
    double meanSquared = 0.0;
    for (int i = 0; i < kRenders; ++i) {
      ReferenceParams params = ReferenceParamsForSpp(spp);
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
    }
    CHECK(SameBytes(outs[0].lightVisibility, outs[i].lightVisibility));
    CHECK(SameBytes(outs[0].depth, outs[i].depth));
    CHECK(outs[0].stats.rays == outs[i].stats.rays);
  }
  CheckWellFormed(outs[0]);
}

TEST_CASE("reference output is finite in degenerate set-ups", "[reference]") {
  ReferenceParams params = ReferenceParamsForSpp(4);
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

}  // namespace
}  // namespace ssgi
