// Highway twin of ViewProjection::PixelRay (core/camera.h) for the passes' SIMD kernels: the same
// operations in the same order, so every target gives its bits (docs/design.md §11;
// tests/core/camera_simd_test.cpp). Lanes are pixels of one row.
//
// A per-target header in Highway's "-inl.h" convention: a *_simd.cpp includes it after
// hwy/highway.h, once per target through hwy/foreach_target.h, outside any namespace.
#if defined(SSGI_CORE_CAMERA_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SSGI_CORE_CAMERA_INL_H_
#undef SSGI_CORE_CAMERA_INL_H_
#else
#define SSGI_CORE_CAMERA_INL_H_
#endif

#include "core/camera.h"
#include "core/math-inl.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

template <class D>
struct RayV {
  Vec3V<D> origin;
  Vec3V<D> direction;
};

// view.PixelRay(px, py) for image positions px (per lane) on one row py.
template <class D>
RayV<D> PixelRayV(D d, const ViewProjection& view, hn::Vec<D> px, float py) {
  const auto sx = hn::Mul(hn::Sub(hn::Div(hn::Mul(hn::Set(d, 2.0f), px), hn::Set(d, float(view.width))),
                                  hn::Set(d, 1.0f)),
                          hn::Set(d, view.halfX));
  const auto sy = hn::Set(d, (1.0f - 2.0f * py / float(view.height)) * view.halfY);
  const auto zero = hn::Zero(d);
  if (view.orthographic) return {{sx, sy, zero}, Set3(d, glm::vec3(0.0f, 0.0f, -1.0f))};
  return {{zero, zero, zero}, {sx, sy, hn::Set(d, -1.0f)}};
}

// PixelRayV with a row per lane.
template <class D>
RayV<D> PixelRayV(D d, const ViewProjection& view, hn::Vec<D> px, hn::Vec<D> py) {
  RayV<D> ray = PixelRayV(d, view, px, 0.0f);
  const auto sy =
      hn::Mul(hn::Sub(hn::Set(d, 1.0f), hn::Div(hn::Mul(hn::Set(d, 2.0f), py), hn::Set(d, float(view.height)))),
              hn::Set(d, view.halfY));
  (view.orthographic ? ray.origin.y : ray.direction.y) = sy;
  return ray;
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#endif  // SSGI_CORE_CAMERA_INL_H_
