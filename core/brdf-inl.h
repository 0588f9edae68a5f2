// Highway twins of the BRDF (core/brdf.h) for the passes' SIMD kernels: the same operations in the
// same order, so every target gives the scalar bits (docs/design.md §11; tests/core/brdf_simd_test.cpp).
// Lanes are shaded points.
//
// A per-target header in Highway's "-inl.h" convention: a *_simd.cpp includes it after
// hwy/highway.h, once per target through hwy/foreach_target.h, outside any namespace.
#if defined(SSGI_CORE_BRDF_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SSGI_CORE_BRDF_INL_H_
#undef SSGI_CORE_BRDF_INL_H_
#else
#define SSGI_CORE_BRDF_INL_H_
#endif

#include "core/brdf.h"
#include "core/math-inl.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

template <class D>
struct SurfaceMaterialV {
  Vec3V<D> albedo;
  hn::Vec<D> metallic;
  hn::Vec<D> roughness;
};

template <class D>
hn::Vec<D> GgxDistributionV(D d, hn::Vec<D> nDotH, hn::Vec<D> alpha) {
  const auto one = hn::Set(d, 1.0f);
  const auto a2 = hn::Mul(alpha, alpha);
  const auto f = hn::Add(hn::Mul(hn::Mul(nDotH, nDotH), hn::Sub(a2, one)), one);
  return hn::Div(a2, hn::Mul(hn::Mul(hn::Set(d, kPi), f), f));
}

// SmithGgxCorrelatedVisibilityCosine(nDotV, nDotL, alpha).
template <class D>
hn::Vec<D> SmithGgxCorrelatedVisibilityCosineV(D d, hn::Vec<D> nDotV, hn::Vec<D> nDotL, hn::Vec<D> alpha) {
  const auto a2 = hn::Mul(alpha, alpha);
  const auto oneMinusA2 = hn::Sub(hn::Set(d, 1.0f), a2);
  const auto lambdaV = hn::Sqrt(hn::Add(hn::Mul(hn::Mul(nDotV, nDotV), oneMinusA2), a2));
  const auto lambdaL = hn::Sqrt(hn::Add(hn::Mul(hn::Mul(nDotL, nDotL), oneMinusA2), a2));
  return hn::Div(hn::Set(d, 0.5f), hn::Add(lambdaV, hn::Mul(hn::Div(nDotV, nDotL), lambdaL)));
}

template <class D>
Vec3V<D> SchlickFresnelV(D d, hn::Vec<D> vDotH, const Vec3V<D>& f0) {
  const auto one = hn::Set(d, 1.0f);
  const auto m = hn::Sub(one, vDotH);
  const auto m2 = hn::Mul(m, m);
  return Add3(f0, Scale3(Sub3(Set3(d, glm::vec3(1.0f)), f0), hn::Mul(hn::Mul(m2, m2), m)));
}

template <class D>
Vec3V<D> SpecularF0V(D d, const SurfaceMaterialV<D>& m) {
  return Mix3(d, Set3(d, glm::vec3(0.04f)), m.albedo, m.metallic);
}

// SpecularWeight(f0, nDotV, roughness), bilinear in `dfgTable` (DfgTableForKernels(), core/brdf.h):
// the table SpecularWeight reads, its A values, then its B values.
template <class D>
Vec3V<D> SpecularWeightV(D d, const Vec3V<D>& f0, hn::Vec<D> nDotV, hn::Vec<D> roughness, const float* dfgTable) {
  const hn::RebindToSigned<D> di;
  const auto zero = hn::Zero(d);
  const auto one = hn::Set(d, 1.0f);
  const auto last = hn::Set(d, float(kDfgSize - 1));
  const auto u = hn::Mul(ClampStd(nDotV, zero, one), last);
  const auto v = hn::Mul(ClampStd(roughness, zero, one), last);
  const auto lastCell = hn::Set(di, kDfgSize - 2);
  const auto i0 = hn::Min(hn::ConvertTo(di, u), lastCell);
  const auto j0 = hn::Min(hn::ConvertTo(di, v), lastCell);
  const auto fu = hn::Sub(u, hn::ConvertTo(d, i0));
  const auto fv = hn::Sub(v, hn::ConvertTo(d, j0));
  struct AbV {
    hn::Vec<D> a, b;
  };
  const auto lerp = [](const AbV& p, const AbV& q, hn::Vec<D> t) -> AbV {
    return {hn::Add(p.a, hn::Mul(hn::Sub(q.a, p.a), t)), hn::Add(p.b, hn::Mul(hn::Sub(q.b, p.b), t))};
  };
  const float* tableA = dfgTable;
  const float* tableB = dfgTable + kDfgSize * kDfgSize;
  const auto entry = hn::Add(hn::Mul(j0, hn::Set(di, kDfgSize)), i0);  // (i0, j0)
  AbV corner[4];  // (i0, j0), (i0 + 1, j0), (i0, j0 + 1), (i0 + 1, j0 + 1)
  // The two corners of a row lie side by side in each plane, and the next row's kDfgSize entries
  // on: when every lane's pair fits one window (one roughness, n.v rising or falling by less than
  // a vector's lanes), four loads serve all eight lookups (GatherWindow, core/math-inl.h), else
  // eight gathers. The same entries either way.
  const GatherWindow<D> window = WindowFromLowest(d, kDfgSize * kDfgSize - kDfgSize, entry, 1);
  if (window.holdsAll) {
    for (int row = 0; row < 2; ++row) {
      const auto a = hn::LoadU(d, tableA + window.first + row * kDfgSize);
      const auto b = hn::LoadU(d, tableB + window.first + row * kDfgSize);
      for (int column = 0; column < 2; ++column) {
        const auto place = hn::IndicesFromVec(d, hn::Add(window.place, hn::Set(di, column)));
        corner[2 * row + column] = {hn::TableLookupLanes(a, place), hn::TableLookupLanes(b, place)};
      }
    }
  } else {
    for (int k = 0; k < 4; ++k) {
      const auto index = hn::Add(entry, hn::Set(di, (k & 1) + kDfgSize * (k >> 1)));
      corner[k] = {hn::GatherIndex(d, tableA, index), hn::GatherIndex(d, tableB, index)};
    }
  }
  const AbV top = lerp(corner[0], corner[1], fu);
  const AbV bottom = lerp(corner[2], corner[3], fu);
  const AbV ab = lerp(top, bottom, fv);
  return Add3(Scale3(f0, ab.a), {ab.b, ab.b, ab.b});
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#endif  // SSGI_CORE_BRDF_INL_H_
