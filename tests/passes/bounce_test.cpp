// The diffuse bounce and ambient occlusion pass (passes/bounce.h): analytic scenes against the
// hemisphere integral they approximate, what thickness does, outputs in range for any input, and
// the Highway twins against the scalar definitions on every compiled target.
#include "passes/bounce.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <limits>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "core/color.h"
#include "core/gbuffer.h"
#include "core/image_io.h"
#include "core/parallel.h"
#include "passes/gbuffer.h"
#include "passes/tonemap.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

std::vector<const Plane<float>*> FloatPlanesOf(const BounceOutputs& out) {
  const BounceHalfRes& h = out.half;
  std::vector<const Plane<float>*> planes{&out.visibility, &h.depth, &h.visibility, &h.horizontalVisibility,
                                          &h.filteredVisibility};
  for (const Plane3<float>* three : {&out.bounce, &h.normal, &h.lit, &h.bounce, &h.horizontalBounce, &h.filteredBounce})
    for (const Plane<float>& plane : three->c) planes.push_back(&plane);
  return planes;
}

bool SameOutputs(const BounceOutputs& a, const BounceOutputs& b) {
  if (!test::SameBytes(a.half.normalCode, b.half.normalCode)) return false;
  const auto pa = FloatPlanesOf(a), pb = FloatPlanesOf(b);
  for (size_t k = 0; k < pa.size(); ++k)
    if (!test::SameBytes(*pa[k], *pb[k])) return false;
  return true;
}

// What the pass reads, owned.
struct PassInputs {
  GBuffer gbuffer;
  ViewProjection view;
  Plane3<float> lit;
};

// A frame's G-buffer and its lit image (direct light plus the sky's diffuse light).
PassInputs FromFrame(const Frame& frame) {
  PassInputs in;
  in.view = frame.view;
  in.gbuffer.normalEncoding = frame.gbuffer.gbuffer.normalEncoding;
  for (int w = 0; w < 4; ++w) {
    const Plane<uint32_t>& source = frame.gbuffer.gbuffer.word[w];
    in.gbuffer.word[w] = MakePlane<uint32_t>(source.xsize(), source.ysize(), 0u);
    for (size_t y = 0; y < source.ysize(); ++y)
      std::copy_n(source.ConstRow(y), source.xsize(), in.gbuffer.word[w].MutableRow(y));
  }
  in.lit = test::CopyOf(frame.Lit());
  return in;
}

// A scene's G-buffer at width x height; the lit image is black until the test fills it.
PassInputs RenderScene(const Scene& scene, int width, int height, NormalEncoding encoding = NormalEncoding::kOct24) {
  PassInputs in;
  in.view = MakePerspective(scene.camera, width, height);
  GBufferOutputs g;
  RunGBuffer({scene, in.view}, {encoding}, g);
  in.gbuffer = std::move(g.gbuffer);
  in.lit = MakePlane3<float>(size_t(width), size_t(height), 0.0f);
  return in;
}

BounceOutputs Run(const PassInputs& in, const BounceParams& params = {}, KernelPath kernels = KernelPath::kSimd) {
  BounceOutputs out;
  RunBounce({in.gbuffer, in.view, in.lit}, params, out, kernels);
  return out;
}

float DepthAt(const PassInputs& in, int x, int y) {
  return UnpackDepth(in.gbuffer.word[GBufferWord::kDepth].ConstRow(size_t(y))[x]);
}

// A lit quad o + a u + b v, a and b in [0, 1], in world space, for the reference integral.
struct Quad {
  glm::dvec3 o, u, v;
  double radiance = 0.0;
};

// What the pass estimates at the world point p on the floor y = 0 (normal +y) of the frame `view`,
// integrated over the hemisphere in double by 300 x 300 stratified cosine-weighted directions: the
// share that meets no quad (visibility) and the mean radiance of the quads met (the bounce, E / pi).
// Only quad points whose image position lies within `reachPixels` of p's count, as the march finds
// no others; the rest of the hemisphere is open.
struct Reference {
  double visibility = 0.0, bounce = 0.0;
};
Reference IntegrateHemisphere(const ViewProjection& view, glm::dvec3 p, const std::vector<Quad>& quads,
                              double reachPixels) {
  constexpr int kN = 300;
  const glm::dmat4 toView(view.view);
  const auto project = [&](glm::dvec3 w) {
    const glm::dvec4 v = toView * glm::dvec4(w, 1.0);
    const double depth = -v.z;
    return glm::dvec2((v.x / (depth * view.halfX) * 0.5 + 0.5) * view.width,
                      (0.5 - v.y / (depth * view.halfY) * 0.5) * view.height);
  };
  const glm::dvec2 centre = project(p);
  Reference r;
  for (int a = 0; a < kN; ++a) {
    for (int b = 0; b < kN; ++b) {
      const double radius = std::sqrt((a + 0.5) / kN), phi = 2.0 * 3.14159265358979 * (b + 0.5) / kN;
      const glm::dvec3 dir(radius * std::cos(phi), std::sqrt(1.0 - radius * radius), radius * std::sin(phi));
      double nearest = std::numeric_limits<double>::infinity(), radiance = 0.0;
      for (const Quad& q : quads) {
        const glm::dvec3 n = glm::cross(q.u, q.v);
        const double along = glm::dot(n, dir);
        if (along == 0.0) continue;
        const double t = glm::dot(n, q.o - p) / along;
        if (!(t > 0.0) || t >= nearest) continue;
        const glm::dvec3 hit = p + t * dir - q.o;
        const double uu = glm::dot(hit, q.u) / glm::dot(q.u, q.u), vv = glm::dot(hit, q.v) / glm::dot(q.v, q.v);
        if (uu < 0.0 || uu > 1.0 || vv < 0.0 || vv > 1.0) continue;
        if (glm::length(project(p + t * dir) - centre) > reachPixels) continue;
        nearest = t;
        radiance = q.radiance;
      }
      if (std::isinf(nearest)) r.visibility += 1.0;
      r.bounce += radiance;
    }
  }
  r.visibility /= double(kN) * kN;
  r.bounce /= double(kN) * kN;
  return r;
}

// The march's reach at view depth d: the radius projected, capped (full-resolution pixels).
double ReachPixels(const ViewProjection& view, const BounceParams& params, double depth) {
  return std::min(double(params.radius) * view.height / (2.0 * view.halfY) / depth, double(params.maxRadiusPixels));
}

// The floor pixel (y = 0) whose world point is nearest `target`; `even` keeps to half-resolution
// sample pixels (both coordinates even).
struct FloorPixel {
  int x = 0, y = 0;
  glm::vec3 world{};
};
FloorPixel NearestFloorPixel(const PassInputs& in, glm::vec3 target, bool even = false) {
  FloorPixel best;
  float bestDistance = std::numeric_limits<float>::infinity();
  for (int y = 0; y < in.view.height; y += even ? 2 : 1) {
    for (int x = 0; x < in.view.width; x += even ? 2 : 1) {
      if (!(DepthAt(in, x, y) < kBackgroundDepth)) continue;
      const glm::vec3 w = test::WorldPosition(in.view, in.gbuffer, x, y);
      if (std::fabs(w.y) > 1e-3f) continue;
      const float distance = glm::length(w - target);
      if (distance < bestDistance) bestDistance = distance, best = {x, y, w};
    }
  }
  return best;
}

TEST_CASE("bounce: an open floor is unoccluded and receives no bounce, exactly", "[bounce]") {
  CameraDesc camera;
  camera.position = {0.0f, 1.5f, 3.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  for (const auto& [width, height] : {std::pair{256, 192}, std::pair{255, 191}}) {
    for (const NormalEncoding encoding : {NormalEncoding::kOct24, NormalEncoding::kXyz8}) {
      Scene scene = test::MakeScene(camera, width, height);
      test::AddGround(scene.mesh, 50.0f);
      PassInputs in = RenderScene(scene, width, height, encoding);
      for (Plane<float>& channel : in.lit.c) channel = MakePlane<float>(size_t(width), size_t(height), 1.0f);
      const BounceOutputs out = Run(in);
      size_t occluded = 0, lit = 0, floor = 0;
      for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
          floor += DepthAt(in, x, y) < kBackgroundDepth;
          occluded += out.visibility.ConstRow(size_t(y))[x] != 1.0f;
          for (const Plane<float>& channel : out.bounce.c) lit += channel.ConstRow(size_t(y))[x] != 0.0f;
        }
      }
      CAPTURE(width, height, int(encoding));
      CHECK(floor > size_t(width) * size_t(height) / 2);
      CHECK(occluded == 0);
      CHECK(lit == 0);
    }
  }
}

// Two walls at 90 degrees on the floor, 3 m tall and 6 m long: x = 0 (facing +x) and z = 0 (facing
// +z), seen from above the open quadrant.
struct Corner {
  static constexpr int kWidth = 256, kHeight = 192;
  PassInputs in;
  std::vector<Quad> walls{{{0, 0, 0}, {0, 0, 6}, {0, 3, 0}, 0.0}, {{0, 0, 0}, {0, 3, 0}, {6, 0, 0}, 0.0}};
  Corner() {
    CameraDesc camera;
    camera.position = {1.2f, 1.0f, 1.2f};
    camera.target = {0.1f, 0.0f, 0.1f};
    Scene scene = test::MakeScene(camera, kWidth, kHeight);
    test::AddGround(scene.mesh, 50.0f);
    for (const Quad& wall : walls) AddQuad(scene.mesh, glm::vec3(wall.o), glm::vec3(wall.u), glm::vec3(wall.v));
    in = RenderScene(scene, kWidth, kHeight);
  }
};

TEST_CASE("bounce: the floor at a box corner sees the quarter of its hemisphere the two walls leave open", "[bounce]") {
  const Corner corner;
  const PassInputs& in = corner.in;
  // A point between infinite walls sees exactly the open quadrant: visibility 1/4 wherever it
  // stands. At 3 mm from the corner, the walls' finite size and the march's reach (directions that
  // meet a wall beyond the radius stay open) make it 0.2536 (the reference integral).
  const FloorPixel p = NearestFloorPixel(in, {0.0f, 0.0f, 0.0f});
  CAPTURE(p.x, p.y, p.world.x, p.world.z);
  REQUIRE(glm::length(p.world) < 0.02f);
  const BounceParams defaults;
  const Reference reference = IntegrateHemisphere(in.view, glm::dvec3(p.world), corner.walls,
                                                  ReachPixels(in.view, defaults, DepthAt(in, p.x, p.y)));
  CHECK(std::fabs(reference.visibility - 0.25) < 0.01);

  // The default pass. Each slice meets the two walls at one sector boundary each, so the sector
  // quantisation (sector centres decide) moves a slice's visibility by at most 2 x 1/64. The filter
  // averages this pixel with floor pixels up to 6 pixels further from the corner (its wall pixels
  // weigh 0), where the reference rises by 0.8 per metre: here 6 pixels are 4 cm, +0.032 at most.
  // Hence |visibility - 1/4| <= 0.01 + 1/32 + 0.032 = 0.074.
  const BounceOutputs out = Run(in, defaults);
  const float visibility = out.visibility.ConstRow(size_t(p.y))[p.x];
  CAPTURE(visibility, reference.visibility);
  CHECK(std::fabs(visibility - 0.25f) <= 0.074f);

  // The march alone, with enough slices and steps that sampling error is small: the unfiltered
  // half-resolution value at the sample pixel nearest the corner within the quantisation's 1/32 of
  // the reference at that pixel (measured: 0.003).
  BounceParams dense;
  dense.slices = 8;
  dense.steps = 32;
  const FloorPixel q = NearestFloorPixel(in, {0.0f, 0.0f, 0.0f}, true);
  const Reference atSample = IntegrateHemisphere(in.view, glm::dvec3(q.world), corner.walls,
                                                 ReachPixels(in.view, dense, DepthAt(in, q.x, q.y)));
  const BounceOutputs denseOut = Run(in, dense);
  const float march = denseOut.half.visibility.ConstRow(size_t(q.y / 2))[q.x / 2];
  CAPTURE(q.x, q.y, march, atSample.visibility);
  CHECK(std::fabs(march - atSample.visibility) <= 1.0 / 32);
}

// A floor with a wall of radiance 1 beside it, x = 0 (facing +x), 0.5 m tall and 40 m long, seen from
// above the floor; every other pixel is black.
struct LitWall {
  static constexpr int kWidth = 256, kHeight = 192;
  static constexpr float kHeightOfWall = 0.5f;
  PassInputs in;
  std::vector<Quad> wall{{{0, 0, -20}, {0, 0, 40}, {0, kHeightOfWall, 0}, 1.0}};
  LitWall() {
    CameraDesc camera;
    camera.position = {2.0f, 3.0f, 2.0f};
    camera.target = {0.4f, 0.0f, 0.0f};
    Scene scene = test::MakeScene(camera, kWidth, kHeight);
    test::AddGround(scene.mesh, 50.0f);
    AddQuad(scene.mesh, glm::vec3(wall[0].o), glm::vec3(wall[0].u), glm::vec3(wall[0].v));
    in = RenderScene(scene, kWidth, kHeight);
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        const bool onWall =
            DepthAt(in, x, y) < kBackgroundDepth && std::fabs(test::WorldPosition(in.view, in.gbuffer, x, y).x) < 1e-3f;
        for (Plane<float>& channel : in.lit.c) channel.MutableRow(size_t(y))[x] = onWall ? 1.0f : 0.0f;
      }
    }
  }
  // The form factor of an infinitely long wall of height h from a floor point at distance x: the
  // cosine-weighted share of the hemisphere it fills, (1 - x / sqrt(x^2 + h^2)) / 2.
  static double FormFactor(double x) {
    return 0.5 * (1.0 - x / std::sqrt(x * x + double(kHeightOfWall) * kHeightOfWall));
  }
};

TEST_CASE("bounce: a lit wall gives the floor beside it its form factor, more the nearer it is", "[bounce]") {
  const LitWall scene;
  const PassInputs& in = scene.in;
  const BounceParams defaults;
  const BounceOutputs out = Run(in, defaults);
  BounceParams dense;
  dense.slices = 8;
  dense.steps = 32;
  const BounceOutputs denseOut = Run(in, dense);
  float previous = std::numeric_limits<float>::infinity();
  for (const float distance : {0.05f, 0.1f, 0.15f, 0.2f, 0.3f, 0.4f}) {
    const FloorPixel p = NearestFloorPixel(in, {distance, 0.0f, 0.0f});
    const Reference reference = IntegrateHemisphere(in.view, glm::dvec3(p.world), scene.wall,
                                                    ReachPixels(in.view, defaults, DepthAt(in, p.x, p.y)));
    const float bounce = out.bounce.c[0].ConstRow(size_t(p.y))[p.x];
    const float visibility = out.visibility.ConstRow(size_t(p.y))[p.x];
    CAPTURE(distance, p.world.x, bounce, reference.bounce, LitWall::FormFactor(p.world.x));
    // The wall is long and the reach covers it: the reference is the closed form within 1 %.
    CHECK(std::fabs(reference.bounce - LitWall::FormFactor(p.world.x)) < 0.01);
    // Every channel alike (a grey light), and every sector the wall covers brings its radiance 1:
    // the bounce is the occluded share, weighted as the visibility is.
    CHECK(out.bounce.c[1].ConstRow(size_t(p.y))[p.x] == bounce);
    CHECK(std::fabs(bounce + visibility - 1.0f) < 1e-5f);
    // The default march finds less than the whole wall: its 4 samples a side miss the part of the
    // wall between the last one below its top and the top (the more, the smaller the wall's image),
    // and quantisation adds at most 1/64 a slice. Bounded above by the reference, and near the
    // wall, where the wall fills much of the reach, within 25 %.
    CHECK(bounce <= reference.bounce + 1.0 / 64);
    if (distance <= 0.1f) CHECK(bounce >= 0.75 * reference.bounce);
    // The bounce grows toward the wall.
    CHECK(bounce < previous);
    previous = bounce;

    // With 8 slices of 32 samples a side, the march alone (unfiltered, at the sample pixel nearest
    // the point) is within 0.03 of the reference: 1/64 of quantisation at the wall's top and the
    // gap below it, now a thirty-second of the radius at most.
    const FloorPixel q = NearestFloorPixel(in, {distance, 0.0f, 0.0f}, true);
    const Reference atSample = IntegrateHemisphere(in.view, glm::dvec3(q.world), scene.wall,
                                                   ReachPixels(in.view, dense, DepthAt(in, q.x, q.y)));
    const float march = denseOut.half.bounce.c[0].ConstRow(size_t(q.y / 2))[q.x / 2];
    CAPTURE(march, atSample.bounce);
    CHECK(std::fabs(march - atSample.bounce) <= 0.03);
  }
}

TEST_CASE("bounce: a thin pole darkens the floor behind it only within its thickness", "[bounce]") {
  constexpr int kWidth = 256, kHeight = 192;
  CameraDesc camera;
  camera.position = {0.0f, 1.6f, 3.0f};
  camera.target = {0.0f, 0.3f, 0.0f};
  Scene scene = test::MakeScene(camera, kWidth, kHeight);
  test::AddGround(scene.mesh, 50.0f);
  // 4 cm square, 1.2 m tall, at the origin; the camera looks at its front (+z) face.
  test::AddBox(scene.mesh, {-0.02f, 0.0f, -0.02f}, {0.02f, 1.2f, 0.02f});
  const PassInputs in = RenderScene(scene, kWidth, kHeight);
  // The least visibility of the floor within 0.3 m of the pole's line of sight, at depths z in [z0, z1].
  const auto darkest = [&](const BounceOutputs& out, float z0, float z1) {
    float least = 1.0f;
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        if (!(DepthAt(in, x, y) < kBackgroundDepth)) continue;
        const glm::vec3 w = test::WorldPosition(in.view, in.gbuffer, x, y);
        if (std::fabs(w.y) > 1e-3f || std::fabs(w.x) > 0.3f || w.z < z0 || w.z > z1) continue;
        least = std::min(least, out.visibility.ConstRow(size_t(y))[x]);
      }
    }
    return least;
  };
  const BounceParams defaults;  // thickness 0.25 m
  BounceParams solid;
  solid.thickness = 100.0f;
  const BounceOutputs thin = Run(in, defaults), thick = Run(in, solid);
  // The floor 0.45 m and more behind the pole's back (-0.02), past its 0.25 m slab and the filter's
  // reach: the pole itself covers about 1 % of the hemisphere there (4 cm seen from 0.45 m, over the
  // angle 2 pi).
  CHECK(darkest(thin, -1.2f, -0.47f) >= 0.96f);
  // Taken as solid far behind its face, the pole casts a deep halo over the same floor.
  CHECK(darkest(thick, -1.2f, -0.47f) < 0.8f);
  // In front of it, where it stands on the floor, it darkens either way.
  CHECK(darkest(thin, 0.02f, 0.12f) < 0.95f);
}

// A random G-buffer and lit image: a smooth depth field with bumps (so that samples occlude), one
// pixel in seven background, some with depths outside the pass's range (0, negative, NaN,
// denormal, 1e30) or at its ends; any normal codes; lit radiance with every special float.
PassInputs RandomInputs(int width, int height, NormalEncoding encoding, std::mt19937& rng) {
  PassInputs in;
  in.view = test::TwinTestViews(width, height)[0];
  in.gbuffer = MakeGBuffer(width, height, encoding);
  in.lit = MakePlane3<float>(size_t(width), size_t(height), 0.0f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const std::vector<float> specials = test::SpecialFloats();
  const float oddDepths[] = {0.0f,   -1.0f, std::numeric_limits<float>::quiet_NaN(),
                             1e-40f, 1e30f, kBounceMinDepth,
                             2e-6f,  9e5f,  kBounceMaxDepth};
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      float d = 4.0f + 0.02f * float(x) + 0.5f * std::sin(0.7f * float(y)) + 0.3f * unit(rng);
      const uint32_t pick = uint32_t(rng()) % 64;
      if (pick < 9)
        d = kBackgroundDepth;
      else if (pick < 11)
        d = oddDepths[rng() % std::size(oddDepths)];
      in.gbuffer.word[GBufferWord::kDepth].MutableRow(size_t(y))[x] = PackDepth(d);
      in.gbuffer.word[GBufferWord::kNormalRoughness].MutableRow(size_t(y))[x] = uint32_t(rng());
      for (Plane<float>& channel : in.lit.c) {
        const bool special = uint32_t(rng()) % 16 == 0;
        channel.MutableRow(size_t(y))[x] = special ? specials[rng() % specials.size()] : 3.0f * unit(rng);
      }
    }
  }
  return in;
}

// Counts the output pixels outside their contracts: visibility in [0, 1] (1 without geometry),
// bounce in [0, 65504] (0 without geometry), never NaN.
size_t BadPixels(const PassInputs& in, const BounceOutputs& out) {
  size_t bad = 0;
  for (int y = 0; y < in.view.height; ++y) {
    for (int x = 0; x < in.view.width; ++x) {
      const float d = DepthAt(in, x, y);
      const bool geometry = d >= kBounceMinDepth && d <= kBounceMaxDepth;
      const float v = out.visibility.ConstRow(size_t(y))[x];
      bad += !(v >= 0.0f && v <= 1.0f) || (!geometry && v != 1.0f);
      for (const Plane<float>& channel : out.bounce.c) {
        const float b = channel.ConstRow(size_t(y))[x];
        bad += !(b >= 0.0f && b <= kMaxRadiance) || (!geometry && b != 0.0f);
      }
    }
  }
  return bad;
}

TEST_CASE("bounce: outputs stay in range for any input, size and setting", "[bounce]") {
  std::mt19937 rng(11);
  std::vector<BounceParams> settings(8);
  settings[1].radius = 0.0f;
  settings[2].maxRadiusPixels = 0.0f;
  settings[3].thickness = 0.0f;
  settings[4].sectors = 1;
  settings[5].slices = kBounceMaxSlices;
  settings[5].steps = kBounceMaxSteps;
  settings[6].radius = 1e6f;
  settings[6].maxRadiusPixels = 1e6f;
  settings[6].thickness = 1e6f;
  settings[7].depthTolerance = 1e-30f;
  for (const auto& [width, height] :
       {std::pair{1, 1}, std::pair{2, 2}, std::pair{3, 1}, std::pair{1, 4}, std::pair{45, 31}}) {
    const PassInputs in = RandomInputs(width, height, NormalEncoding::kOct24, rng);
    for (size_t k = 0; k < settings.size(); ++k) {
      CAPTURE(width, height, k);
      CHECK(BadPixels(in, Run(in, settings[k])) == 0);
    }
  }
  // Grazing normals: every pixel's normal perpendicular to its view ray, on a random depth field.
  PassInputs grazing = RandomInputs(40, 30, NormalEncoding::kOct24, rng);
  for (int y = 0; y < 30; ++y) {
    for (int x = 0; x < 40; ++x) {
      const glm::vec3 ray = grazing.view.PixelRay(float(x) + 0.5f, float(y) + 0.5f).direction;
      const glm::vec3 n = glm::normalize(glm::cross(ray, glm::vec3(0.3f, 1.0f, 0.1f)));
      grazing.gbuffer.word[GBufferWord::kNormalRoughness].MutableRow(size_t(y))[x] =
          EncodeNormal(n, NormalEncoding::kOct24);
    }
  }
  CHECK(BadPixels(grazing, Run(grazing)) == 0);
}

TEST_CASE("bounce: the SIMD kernels give the scalar bytes on every target, random G-buffers at odd sizes",
          "[bounce][simd]") {
  std::mt19937 rng(20230126);
  BounceParams params;
  params.radius = 2.0f;
  size_t occluded = 0, lit = 0;
  for (const auto& [width, height] : {std::pair{1, 1}, std::pair{2, 1}, std::pair{1, 2}, std::pair{3, 3},
                                      std::pair{5, 7}, std::pair{33, 2}, std::pair{2, 33}, std::pair{67, 45}}) {
    for (const NormalEncoding encoding : {NormalEncoding::kOct24, NormalEncoding::kXyz8}) {
      const PassInputs in = RandomInputs(width, height, encoding, rng);
      for (const int sectors : {32, 7}) {
        params.sectors = sectors;
        params.slices = sectors == 32 ? 2 : 3;
        params.steps = sectors == 32 ? 4 : 3;
        const auto run = [&](KernelPath kernels) { return Run(in, params, kernels); };
        CAPTURE(width, height, int(encoding), sectors);
        CHECK(test::TargetsWhereKernelPathsDiffer(run, SameOutputs) == "");
        const BounceOutputs out = run(KernelPath::kScalar);
        for (size_t y = 0; y < out.half.visibility.ysize(); ++y) {
          for (size_t x = 0; x < out.half.visibility.xsize(); ++x) {
            occluded += out.half.visibility.ConstRow(y)[x] < 1.0f;
            lit += out.half.bounce.c[0].ConstRow(y)[x] > 0.0f;
          }
        }
      }
    }
  }
  // The random depths occlude and light, so the comparisons cover the march's every step.
  CHECK(occluded > 1000);
  CHECK(lit > 1000);
}

TEST_CASE("bounce: the SIMD kernels give the scalar bytes on every target on the default scene", "[bounce][simd]") {
  const test::DefaultScene scene = test::LoadDefaultScene();
  for (const auto& [width, height] :
       {std::pair{1024, 1024}, std::pair{1023, 769}, std::pair{67, 45}, std::pair{1, 1}}) {
    const PassInputs in = FromFrame(scene.Render(width, height));
    const auto run = [&](KernelPath kernels) { return Run(in, {}, kernels); };
    CAPTURE(width, height);
    CHECK(test::TargetsWhereKernelPathsDiffer(run, SameOutputs) == "");
  }
}

TEST_CASE("bounce: the SIMD row kernels equal the scalar ones and write nothing past a row", "[bounce][simd]") {
  std::mt19937 rng(5);
  for (int halfWidth = 1; halfWidth <= 40; ++halfWidth) {
    for (const int width : {2 * halfWidth - 1, 2 * halfWidth}) {
      const PassInputs in = RandomInputs(width, 9, NormalEncoding::kOct24, rng);
      BounceParams params;
      params.radius = 3.0f;
      const BounceOutputs out = Run(in, params, KernelPath::kScalar);
      const BounceSetup setup = MakeBounceSetup(in.view, params, in.gbuffer.normalEncoding);
      const BounceHalfRes& h = out.half;
      BounceHalfView view{};
      view.stride = size_t(h.depth.PixelsPerRow());
      view.depth = h.depth.ConstRow(0);
      view.normalCode = h.normalCode.ConstRow(0);
      view.filteredVisibility = h.filteredVisibility.ConstRow(0);
      for (int c = 0; c < 3; ++c) {
        view.normal[c] = h.normal.c[c].ConstRow(0);
        view.lit[c] = h.lit.c[c].ConstRow(0);
        view.filteredBounce[c] = h.filteredBounce.c[c].ConstRow(0);
      }
      const float* marchBounce[3] = {h.bounce.c[0].ConstRow(0), h.bounce.c[1].ConstRow(0), h.bounce.c[2].ConstRow(0)};
      // Each kernel into rows one float longer than the row, -1 before: the twins must agree on the
      // row and leave the extra float alone. `rows` outputs, `length` floats a row.
      const auto compare = [&](const char* kernel, int y, size_t length, size_t rows, const auto& call) {
        std::vector<std::vector<float>> expected(rows, std::vector<float>(length + 1, -1.0f)), actual = expected;
        std::vector<uint32_t> expectedCodes(length + 1, 0xFFFFFFFFu), actualCodes = expectedCodes;
        call(KernelPath::kScalar, expected, expectedCodes.data());
        test::ForEachSimdTarget([&](const char* target) {
          for (std::vector<float>& row : actual) std::fill(row.begin(), row.end(), -1.0f);
          std::fill(actualCodes.begin(), actualCodes.end(), 0xFFFFFFFFu);
          call(KernelPath::kSimd, actual, actualCodes.data());
          for (size_t r = 0; r < rows; ++r) {
            CAPTURE(kernel, target, width, y, r);
            REQUIRE(test::FirstDifferentBits(actual[r].data(), expected[r].data(), length + 1) == length + 1);
          }
          REQUIRE(actualCodes == expectedCodes);
        });
      };
      for (int j = 0; j < setup.halfHeight; ++j) {
        compare("prepare", j, size_t(halfWidth), 7, [&](KernelPath k, auto& rows, uint32_t* codes) {
          const uint32_t* words[2] = {in.gbuffer.word[1].ConstRow(size_t(2 * j)),
                                      in.gbuffer.word[2].ConstRow(size_t(2 * j))};
          const float* litRow[3] = {in.lit.c[0].ConstRow(size_t(2 * j)), in.lit.c[1].ConstRow(size_t(2 * j)),
                                    in.lit.c[2].ConstRow(size_t(2 * j))};
          float* normal[3] = {rows[1].data(), rows[2].data(), rows[3].data()};
          float* lit[3] = {rows[4].data(), rows[5].data(), rows[6].data()};
          (k == KernelPath::kSimd ? BouncePrepareRowSimd : BouncePrepareRowScalar)(setup, words[0], words[1], litRow,
                                                                                   rows[0].data(), normal, codes, lit);
        });
        compare("march", j, size_t(halfWidth), 4, [&](KernelPath k, auto& rows, uint32_t*) {
          float* bounce[3] = {rows[1].data(), rows[2].data(), rows[3].data()};
          (k == KernelPath::kSimd ? BounceMarchRowSimd : BounceMarchRowScalar)(setup, view, j, rows[0].data(), bounce);
        });
        for (const bool vertical : {false, true}) {
          compare("filter", j, size_t(halfWidth), 4, [&](KernelPath k, auto& rows, uint32_t*) {
            float* bounce[3] = {rows[1].data(), rows[2].data(), rows[3].data()};
            (k == KernelPath::kSimd ? BounceFilterRowSimd : BounceFilterRowScalar)(
                setup, view, j, vertical, h.visibility.ConstRow(0), marchBounce, rows[0].data(), bounce);
          });
        }
      }
      for (int y = 0; y < 9; ++y) {
        compare("upsample", y, size_t(width), 4, [&](KernelPath k, auto& rows, uint32_t*) {
          float* bounce[3] = {rows[1].data(), rows[2].data(), rows[3].data()};
          (k == KernelPath::kSimd ? BounceUpsampleRowSimd : BounceUpsampleRowScalar)(
              setup, view, y, in.gbuffer.word[1].ConstRow(size_t(y)), in.gbuffer.word[2].ConstRow(size_t(y)),
              rows[0].data(), bounce);
        });
      }
    }
  }
}

TEST_CASE("bounce: the same bytes at 1, 2 and 3 threads, and into kept outputs", "[bounce]") {
  std::mt19937 rng(3);
  const PassInputs in = RandomInputs(257, 131, NormalEncoding::kOct24, rng);
  std::vector<BounceOutputs> outputs;
  std::vector<uint64_t> taps;
  for (int threads = 1; threads <= 3; ++threads) {
    const ThreadLimit limit(threads);
    BounceOutputs out;
    taps.push_back(RunBounce({in.gbuffer, in.view, in.lit}, {}, out).taps);
    outputs.push_back(std::move(out));
  }
  for (size_t k = 1; k < 3; ++k) {
    CHECK(SameOutputs(outputs[k], outputs[0]));
    CHECK(taps[k] == taps[0]);
  }
  CHECK(taps[0] > 0);
  // Outputs kept from another frame (another size, then this one's with other contents) are
  // reshaped or overwritten: the same bytes.
  BounceOutputs kept;
  RunBounce({in.gbuffer, in.view, in.lit}, {}, kept);
  const PassInputs other = RandomInputs(100, 60, NormalEncoding::kOct24, rng);
  RunBounce({other.gbuffer, other.view, other.lit}, {}, kept);
  RunBounce({in.gbuffer, in.view, in.lit}, {}, kept);
  CHECK(SameOutputs(kept, outputs[0]));
}

// Not a check but the accuracy of settings (hidden; run it by its tag): for slices x steps, the
// mean and worst error of the full pass's bounce beside the lit wall (floor points 0.05 to 0.4 m from
// it) against the reference integral, and its visibility at the box corner against 1/4.
TEST_CASE("bounce: accuracy of the settings", "[.bounce_accuracy]") {
  const LitWall wall;
  const Corner corner;
  struct Probe {
    FloorPixel pixel;
    Reference reference;
  };
  std::vector<Probe> probes;
  const BounceParams defaults;
  for (const float distance : {0.05f, 0.1f, 0.15f, 0.2f, 0.3f, 0.4f}) {
    const FloorPixel p = NearestFloorPixel(wall.in, {distance, 0.0f, 0.0f});
    probes.push_back({p, IntegrateHemisphere(wall.in.view, glm::dvec3(p.world), wall.wall,
                                             ReachPixels(wall.in.view, defaults, DepthAt(wall.in, p.x, p.y)))});
  }
  const FloorPixel atCorner = NearestFloorPixel(corner.in, {0.0f, 0.0f, 0.0f});
  {
    const BounceOutputs out = Run(wall.in, defaults);
    std::printf("defaults, lit wall (distance: bounce / reference / form factor):");
    for (const Probe& probe : probes)
      std::printf(" %.2f: %.3f / %.3f / %.3f", probe.pixel.world.x,
                  out.bounce.c[0].ConstRow(size_t(probe.pixel.y))[probe.pixel.x], probe.reference.bounce,
                  LitWall::FormFactor(probe.pixel.world.x));
    std::printf("\n");
  }
  for (const int slices : {1, 2, 3, 4}) {
    for (const int steps : {2, 4, 6, 8, 12}) {
      BounceParams params;
      params.slices = slices;
      params.steps = steps;
      const BounceOutputs out = Run(wall.in, params);
      double sum = 0.0, worst = 0.0;
      for (const Probe& probe : probes) {
        const double error = out.bounce.c[0].ConstRow(size_t(probe.pixel.y))[probe.pixel.x] - probe.reference.bounce;
        sum += std::fabs(error);
        worst = std::max(worst, std::fabs(error));
      }
      const BounceOutputs cornerOut = Run(corner.in, params);
      std::printf("slices %d steps %2d: wall bounce error mean %.3f worst %.3f; corner visibility %.3f (1/4)\n", slices,
                  steps, sum / double(probes.size()), worst,
                  cornerOut.visibility.ConstRow(size_t(atCorner.y))[atCorner.x]);
    }
  }
}

// Writes planes (values times `scale`, clamped) as an 8-bit sRGB PNG, grey (one plane three times)
// or RGB: the region crop = {x, y, width, height} (all when empty), each pixel zoom x zoom times.
void WritePicture(const std::filesystem::path& path, const Plane<float>* const channels[3], float scale,
                  std::vector<int> crop = {}, int zoom = 1) {
  if (crop.empty()) crop = {0, 0, int(channels[0]->xsize()), int(channels[0]->ysize())};
  const int width = crop[2] * zoom, height = crop[3] * zoom;
  std::vector<uint8_t> rgb(size_t(width) * size_t(height) * 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        rgb[(size_t(y) * size_t(width) + size_t(x)) * 3 + size_t(c)] =
            TonemapCode(channels[c]->ConstRow(size_t(crop[1] + y / zoom))[crop[0] + x / zoom] * scale, Tonemap::kClamp);
  WritePng(path, width, height, rgb);
}

// Not a check but the pictures to look at (hidden; run it by its tag): the default scene at
// 1024x1024 with its lit image (direct plus sky light), the settings from BOUNCE_SLICES,
// BOUNCE_STEPS and BOUNCE_THICKNESS when set. Writes to /tmp: bounce_ao.png (visibility),
// bounce_bounce.png (bounce x 4), their 280x280 crops around the spheres 3x enlarged, the bounce and
// the lit image around the black pawn 3x enlarged (bounce_pawn_crop.png, bounce_pawn_lit_crop.png),
// bounce_ao_march.png (the unfiltered half-resolution visibility), bounce_lit.png (the input, which
// is also the frame's result without reflections and bounce) and bounce_shaded.png (the direct light, plus the
// sky's diffuse light times the visibility, plus albedo (1 - metallic) bounce: the frame's composite
// without its specular terms).
TEST_CASE("bounce: pictures of the default scene", "[.bounce_pictures]") {
  const test::DefaultScene scene = test::LoadDefaultScene();
  const Frame frame = scene.Render(1024, 1024);
  const PassInputs in = FromFrame(frame);
  BounceParams params;
  if (const char* value = std::getenv("BOUNCE_SLICES")) params.slices = std::atoi(value);
  if (const char* value = std::getenv("BOUNCE_STEPS")) params.steps = std::atoi(value);
  if (const char* value = std::getenv("BOUNCE_THICKNESS")) params.thickness = float(std::atof(value));
  BounceOutputs out;
  const BounceStats stats = RunBounce({in.gbuffer, in.view, in.lit}, params, out);
  std::printf("bounce: %.2f ms (prepare %.2f, march %.2f, filter %.2f, upsample %.2f), %llu taps\n", stats.ms,
              stats.prepareMs, stats.marchMs, stats.filterMs, stats.upsampleMs, (unsigned long long)stats.taps);
  const Plane<float>* ao[3] = {&out.visibility, &out.visibility, &out.visibility};
  const Plane<float>* bounce[3] = {&out.bounce.c[0], &out.bounce.c[1], &out.bounce.c[2]};
  const Plane<float>* march[3] = {&out.half.visibility, &out.half.visibility, &out.half.visibility};
  const Plane<float>* lit[3] = {&in.lit.c[0], &in.lit.c[1], &in.lit.c[2]};
  WritePicture("/tmp/bounce_ao.png", ao, 1.0f);
  WritePicture("/tmp/bounce_bounce.png", bounce, 4.0f);
  WritePicture("/tmp/bounce_ao_crop.png", ao, 1.0f, {380, 380, 280, 280}, 3);
  WritePicture("/tmp/bounce_bounce_crop.png", bounce, 4.0f, {380, 380, 280, 280}, 3);
  WritePicture("/tmp/bounce_pawn_crop.png", bounce, 4.0f, {780, 540, 200, 230}, 3);
  WritePicture("/tmp/bounce_pawn_lit_crop.png", lit, 1.0f, {780, 540, 200, 230}, 3);
  WritePicture("/tmp/bounce_ao_march.png", march, 1.0f);
  WritePicture("/tmp/bounce_lit.png", lit, 1.0f);
  Plane3<float> shaded = test::CopyOf(frame.direct.radiance);
  for (int y = 0; y < 1024; ++y) {
    for (int x = 0; x < 1024; ++x) {
      if (!(DepthAt(in, x, y) < kBackgroundDepth)) continue;
      const uint32_t word0 = in.gbuffer.word[GBufferWord::kAlbedoMetallic].ConstRow(size_t(y))[x];
      const glm::vec3 diffuse = UnpackAlbedo(word0) * (1.0f - UnpackMetallic(word0));
      const float visibility = out.visibility.ConstRow(size_t(y))[x];
      for (int c = 0; c < 3; ++c) {
        const float sky = frame.sky ? frame.skyLight.diffuse.c[c].ConstRow(size_t(y))[x] : 0.0f;
        shaded.c[c].MutableRow(size_t(y))[x] += sky * visibility + diffuse[c] * out.bounce.c[c].ConstRow(size_t(y))[x];
      }
    }
  }
  const Plane<float>* shadedPlanes[3] = {&shaded.c[0], &shaded.c[1], &shaded.c[2]};
  WritePicture("/tmp/bounce_shaded.png", shadedPlanes, 1.0f);
}

}  // namespace
}  // namespace ssgi
