// The Highway twin of ViewProjection::PixelRay (core/camera-inl.h) against the scalar function, bit
// for bit, on every compiled and supported target: perspective views of odd and even sizes and an
// orthographic view, at every pixel centre of a few rows and at arbitrary image positions.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tests/core/camera_simd_test.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "core/camera-inl.h"
#include "core/row-inl.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<float>;

// in: px; out: origin, direction (three rows each) of the rays through (px, py).
void PixelRays(const ViewProjection& view, float py, const float* const* in, size_t count, float* const* out) {
  const D d;
  for (size_t x = 0; x < count; x += hn::Lanes(d)) {
    const RayV<D> ray = PixelRayV(d, view, LoadRow(d, in[0], x, count, 0.0f), py);
    StoreRow3(ray.origin, d, out, x, count);
    StoreRow3(ray.direction, d, out + 3, x, count);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "tests/simd_rows.h"

namespace ssgi {
HWY_EXPORT(PixelRays);

namespace {

TEST_CASE("camera: PixelRayV equals ViewProjection::PixelRay on every target", "[camera][simd]") {
  CameraDesc camera;
  camera.position = {0.3f, 2.7f, 5.6f};
  camera.target = {0.0f, 0.25f, -0.05f};
  camera.fovYDegrees = 40.0f;
  const ViewProjection views[] = {
      MakePerspective(camera, 1, 1),
      MakePerspective(camera, 67, 45),
      MakePerspective(camera, 1024, 1024),
      MakeOrthographic({0.0f, 5.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 3.0f, 2.0f, 0.1f, 20.0f, 61, 37),
  };
  std::mt19937 rng(14);
  for (const ViewProjection& view : views) {
    // Every pixel centre of the row, then positions anywhere around the image.
    const size_t count = size_t(view.width) + 100;
    std::uniform_real_distribution<float> around(-10.0f, float(view.width) + 10.0f);
    for (const float py : {0.5f, float(view.height) - 0.5f, 0.5f * float(view.height), -3.25f}) {
      test::SimdRows in(1, count), expected(6, count);
      for (size_t i = 0; i < count; ++i) {
        const float px = i < size_t(view.width) ? float(i) + 0.5f : around(rng);
        in.values[0][i] = px;
        const ViewProjection::Ray ray = view.PixelRay(px, py);
        expected.Set3(0, i, ray.origin);
        expected.Set3(3, i, ray.direction);
      }
      CAPTURE(view.width, view.height, view.orthographic, py);
      test::CheckEveryTarget(expected, count, [&](float* const* out) {
        HWY_DYNAMIC_DISPATCH(PixelRays)(view, py, in.in.data(), count, out);
      });
    }
  }
}

}  // namespace
}  // namespace ssgi
#endif
