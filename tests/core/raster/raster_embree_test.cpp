// The rasterizer's primary visibility against Embree's (docs/design.md §10): the same triangles, the same
// camera, one ray through every pixel centre. Depth may differ only by rounding and the 1/256-pixel
// vertex snapping, except on silhouettes, where snapping legitimately moves coverage by a pixel.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

#include <catch2/catch.hpp>
#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/plane.h"
#include "core/procedural_mesh.h"
#include "core/raster/raster.h"
#include "core/scene.h"
#include "passes/gbuffer.h"

namespace ssgi {
namespace {

constexpr int kWidth = 256;
constexpr int kHeight = 192;
// Float depth keys and snapping keep faces seen at up to ~85 degrees within this.
constexpr double kDepthTolerance = 1e-4;
// A relative depth step between 4-neighbours larger than this is a discontinuity (silhouette or
// self-occlusion edge). Faces seen at up to ~78 degrees step by less than this per pixel here, and
// snapping moves depth by more than kDepthTolerance only beyond ~85 degrees.
constexpr double kEdgeJump = 0.02;
constexpr double kMinAgreeingFraction = 0.995;

constexpr int kTubularSegments = 128;
constexpr int kRadialSegments = 16;

Scene KnotScene() {
  Scene scene;
  scene.mesh = MakeTorusKnot(kTubularSegments, kRadialSegments);  // 4096 triangles
  scene.materials.push_back(Material{});
  scene.camera.position = {0.8f, 1.6f, 3.6f};
  scene.camera.target = {0.0f, 0.0f, 0.0f};
  scene.camera.fovYDegrees = 45.0f;
  return scene;
}

// View depth per pixel, +infinity where nothing is hit.
using DepthImage = std::vector<double>;

class EmbreeScene {
 public:
  explicit EmbreeScene(const Mesh& mesh) {
    device_ = rtcNewDevice(nullptr);
    REQUIRE(device_ != nullptr);
    scene_ = rtcNewScene(device_);
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree's own buffers: it pads them for its 16-byte vertex loads, which a tightly packed
    // std::vector<glm::vec3> shared in place would read past.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
    std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
    auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), mesh.TriangleCount()));
    std::memcpy(indices, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
    REQUIRE(rtcGetDeviceError(device_) == RTC_ERROR_NONE);
  }
  ~EmbreeScene() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Primary rays through the pixel centres of `view`. Embree has no back-face culling here, which
  // cannot matter for a closed mesh: the first surface a ray from outside meets is a front face.
  DepthImage Depth(const ViewProjection& view) const {
    const glm::mat4 viewToWorld = glm::inverse(view.view);
    const glm::vec3 origin(viewToWorld[3]);
    const glm::mat3 viewRotation(view.view);
    DepthImage depth(size_t(view.width) * size_t(view.height));
    for (int y = 0; y < view.height; ++y) {
      for (int x = 0; x < view.width; ++x) {
        const ViewProjection::Ray viewRay = view.PixelRay(float(x) + 0.5f, float(y) + 0.5f);
        const glm::vec3 direction = glm::mat3(viewToWorld) * viewRay.direction;
        RTCRayHit rayHit{};
        rayHit.ray.org_x = origin.x;
        rayHit.ray.org_y = origin.y;
        rayHit.ray.org_z = origin.z;
        rayHit.ray.dir_x = direction.x;
        rayHit.ray.dir_y = direction.y;
        rayHit.ray.dir_z = direction.z;
        rayHit.ray.tnear = 0.0f;
        rayHit.ray.tfar = std::numeric_limits<float>::infinity();
        rayHit.ray.mask = 0xFFFFFFFFu;
        rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        rtcIntersect1(scene_, &context, &rayHit);
        // t is in units of the (non-unit) direction; its view-space z component is -1 up to the
        // rounding of the round trip through world space, so view depth is t * -z.
        const double viewZ = double((viewRotation * direction).z);
        depth[size_t(y) * view.width + x] = rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID
                                                ? std::numeric_limits<double>::infinity()
                                                : double(rayHit.ray.tfar) * -viewZ;
      }
    }
    return depth;
  }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

DepthImage GBufferDepth(const GBuffer& gbuffer) {
  DepthImage depth(size_t(gbuffer.width()) * size_t(gbuffer.height()));
  for (int y = 0; y < gbuffer.height(); ++y) {
    const uint32_t* row = gbuffer.word[GBufferWord::kDepth].ConstRow(y);
    for (int x = 0; x < gbuffer.width(); ++x) depth[size_t(y) * gbuffer.width() + x] = UnpackDepth(row[x]);
  }
  return depth;
}

bool Discontinuous(double a, double b) {
  if (std::isinf(a) || std::isinf(b)) return std::isinf(a) != std::isinf(b);
  return std::fabs(a - b) > kEdgeJump * std::min(a, b);
}

// Pixels with a 4-neighbour across a coverage edge or a depth discontinuity in either image.
std::vector<bool> SilhouettePixels(const DepthImage& a, const DepthImage& b, int width, int height) {
  std::vector<bool> silhouette(a.size(), false);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * width + x;
      const int neighbours[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
      for (const auto& [nx, ny] : neighbours) {
        if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
        const size_t j = size_t(ny) * width + nx;
        if (Discontinuous(a[i], a[j]) || Discontinuous(b[i], b[j])) silhouette[i] = true;
      }
    }
  }
  return silhouette;
}

// Pixels next to a 4-neighbour showing a part of the knot far away along it: where one strand of
// the knot hides another.
size_t SelfOcclusionPixels(const Plane<uint32_t>& triangles) {
  const auto along = [](uint32_t triangle) { return int(triangle / (2 * kRadialSegments)); };
  const auto farApart = [&](uint32_t a, uint32_t b) {
    if (a == kNoTriangle || b == kNoTriangle) return false;
    const int step = std::abs(along(a) - along(b));
    return std::min(step, kTubularSegments - step) > kTubularSegments / 8;
  };
  size_t count = 0;
  for (int y = 0; y + 1 < int(triangles.ysize()); ++y) {
    for (int x = 0; x + 1 < int(triangles.xsize()); ++x) {
      const uint32_t t = triangles.ConstRow(y)[x];
      if (farApart(t, triangles.ConstRow(y)[x + 1]) || farApart(t, triangles.ConstRow(y + 1)[x])) ++count;
    }
  }
  return count;
}


TEST_CASE("rasterized view depth matches Embree primary rays", "[raster][embree]") {
  const Scene scene = KnotScene();
  const ViewProjection view = MakePerspective(scene.camera, kWidth, kHeight);
  GBufferOutputs out;
  RunGBuffer({scene, view}, GBufferParams{}, out);
  const DepthImage raster = GBufferDepth(out.gbuffer);
  const DepthImage traced = EmbreeScene(scene.mesh).Depth(view);
  const std::vector<bool> silhouette = SilhouettePixels(raster, traced, kWidth, kHeight);

  const size_t selfOcclusion = SelfOcclusionPixels(out.visibility.triangle);
  size_t coveredEither = 0, agreeing = 0, coverageMismatches = 0, onSilhouettes = 0;
  size_t offSilhouetteDisagreements = 0, offSilhouetteCoverageMismatches = 0;
  double maxAgreeingError = 0.0, maxOffSilhouetteError = 0.0;
  for (size_t i = 0; i < raster.size(); ++i) {
    const bool rasterHit = !std::isinf(raster[i]), tracedHit = !std::isinf(traced[i]);
    if (!rasterHit && !tracedHit) continue;
    ++coveredEither;
    if (silhouette[i]) ++onSilhouettes;
    if (rasterHit != tracedHit) {
      ++coverageMismatches;
      if (!silhouette[i]) ++offSilhouetteCoverageMismatches;
      continue;
    }
    const double error = std::fabs(raster[i] - traced[i]) / traced[i];
    if (!silhouette[i]) maxOffSilhouetteError = std::max(maxOffSilhouetteError, error);
    if (error <= kDepthTolerance) {
      ++agreeing;
      maxAgreeingError = std::max(maxAgreeingError, error);
    } else if (!silhouette[i]) {
      ++offSilhouetteDisagreements;
    }
  }
  const double agreeingFraction = double(agreeing) / double(coveredEither);
  WARN("raster vs Embree, " << kWidth << "x" << kHeight << ", " << scene.mesh.TriangleCount()
                            << " triangles: " << coveredEither << " pixels covered by either (" << onSilhouettes
                            << " on silhouettes), agreeing "
                            << agreeingFraction << " (rel. tol " << kDepthTolerance << "), max rel. error "
                            << maxAgreeingError << " on agreeing pixels, " << maxOffSilhouetteError
                            << " off silhouettes; " << coverageMismatches << " coverage mismatches, "
                            << selfOcclusion << " pixels on self-occlusion edges");

  // The scene must exercise what the comparison is about: background, silhouettes, self-occlusion.
  REQUIRE(coveredEither > size_t(kWidth * kHeight) / 4);
  REQUIRE(coveredEither < size_t(kWidth * kHeight) * 3 / 4);
  REQUIRE(selfOcclusion > 100);

  CHECK(agreeingFraction >= kMinAgreeingFraction);
  CHECK(offSilhouetteDisagreements == 0);
  CHECK(offSilhouetteCoverageMismatches == 0);
}

}  // namespace
}  // namespace ssgi
