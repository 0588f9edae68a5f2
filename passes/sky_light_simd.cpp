// The Highway twin of SkyLightRowScalar (sky_light.cpp): the same operations in the same order, so
// every target gives the scalar bits (tests/passes/sky_light_test.cpp checks each compiled target).
// Lanes are pixels of the row; the sky-visibility volume is read by gathers.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/sky_light_simd.cpp"
// clang-format off: foreach_target.h must come first, then highway.h, then the per-target headers.
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
// clang-format on

#include "core/color.h"
#include "core/environment_lighting-inl.h"
#include "core/gbuffer-inl.h"
#include "core/row-inl.h"
#include "passes/sky_light.h"
#include "passes/world_bounce.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The most distinct cells a corner's lanes may read for their values to be broadcast and selected
// rather than gathered: a run of pixels across a boundary in x and one in y or z reads four; a
// 16-lane gather costs about as much as four broadcasts and selects per lane set.
constexpr int kMostSelectedCells = 4;

// SampleVolume(volume, position, normal) per lane: each corner's first coefficient, the weights.
template <class D>
struct VolumeSampleV {
  hn::Vec<hn::RebindToSigned<D>> corner[8];
  hn::Vec<D> f[3];
  // Every lane reads the same cells (neighbouring pixels mostly lie in one): their values are
  // loaded once and broadcast instead of gathered.
  bool oneCell;
  // Else, per corner (every table of the grid has the same layout, so these serve them all): where
  // the lanes read at most two cells (a run of pixels across one cell boundary), or at most
  // kMostSelectedCells where the corner's window of the table does not hold every lane's four
  // coefficients, the cells' values broadcast and selected (`cells` > 0: cell[0] everywhere, then
  // cell[j] in lanes `in[j]`); else where the window holds them, one load gives them; else gathered.
  int cells[8];
  int32_t cell[8][kMostSelectedCells];
  hn::Mask<D> in[8][kMostSelectedCells];
  GatherWindow<D> window[8];
};

// The distinct values of `index` in lane order of first appearance, up to kMostSelectedCells, and the
// lanes holding each; 0 where there are more.
template <class D>
int DistinctCells(D d, hn::Vec<hn::RebindToSigned<D>> index, int32_t (&cell)[kMostSelectedCells],
                  hn::Mask<D> (&in)[kMostSelectedCells]) {
  const hn::RebindToSigned<D> di;
  auto remaining = hn::FirstN(di, hn::Lanes(di));
  for (int j = 0; j < kMostSelectedCells; ++j) {
    cell[j] = hn::ExtractLane(index, hn::FindKnownFirstTrue(di, remaining));
    const auto same = hn::Eq(index, hn::Set(di, cell[j]));
    in[j] = hn::RebindMask(d, same);
    remaining = hn::AndNot(same, remaining);
    if (hn::AllFalse(di, remaining)) return j + 1;
  }
  return 0;
}

template <class D>
VolumeSampleV<D> SampleVolumeV(D d, const SkyVisibilityVolume& volume, const Vec3V<D>& position,
                               const Vec3V<D>& normal) {
  const hn::RebindToSigned<D> di;
  const auto offset = hn::Set(d, 0.5f * volume.cellSize);
  const auto inverse = hn::Set(d, volume.inverseCellSize);
  const auto half = hn::Set(d, 0.5f);
  const Vec3V<D> origin = Set3(d, volume.origin);
  const auto q = [&](hn::Vec<D> p, hn::Vec<D> n, hn::Vec<D> o) {
    return hn::Sub(hn::Mul(hn::Sub(hn::Add(p, hn::Mul(n, offset)), o), inverse), half);
  };
  const hn::Vec<D> qs[3] = {q(position.x, normal.x, origin.x), q(position.y, normal.y, origin.y),
                            q(position.z, normal.z, origin.z)};
  const int cells[3] = {volume.cellsX, volume.cellsY, volume.cellsZ};
  hn::Vec<decltype(di)> i0[3], i1[3];
  VolumeSampleV<D> sample;
  for (int a = 0; a < 3; ++a) {
    const auto c = ClampStd(qs[a], hn::Zero(d), hn::Set(d, float(cells[a] - 1)));
    i0[a] = hn::ConvertTo(di, c);
    i1[a] = hn::Min(hn::Add(i0[a], hn::Set(di, 1)), hn::Set(di, cells[a] - 1));
    sample.f[a] = hn::Sub(c, hn::ConvertTo(d, i0[a]));
  }
  const auto rowStride = hn::Set(di, volume.cellsX);
  const auto sliceStride = hn::Set(di, volume.cellsX * volume.cellsY);
  for (int corner = 0; corner < 8; ++corner) {
    const auto x = corner & 1 ? i1[0] : i0[0], y = corner & 2 ? i1[1] : i0[1], z = corner & 4 ? i1[2] : i0[2];
    sample.corner[corner] = hn::ShiftLeft<2>(hn::Add(hn::Add(hn::Mul(z, sliceStride), hn::Mul(y, rowStride)), x));
  }
  sample.oneCell = hn::AllTrue(di, hn::Eq(sample.corner[0], hn::Set(di, hn::GetLane(sample.corner[0])))) &&
                   hn::AllTrue(di, hn::Eq(sample.corner[7], hn::Set(di, hn::GetLane(sample.corner[7]))));
  if (!sample.oneCell) {
    const int32_t tableSize = int32_t(volume.coefficients.size());
    for (int corner = 0; corner < 8; ++corner) {
      int& count = sample.cells[corner];
      count = DistinctCells(d, sample.corner[corner], sample.cell[corner], sample.in[corner]);
      if (count == 1 || count == 2) continue;
      sample.window[corner] = WindowFromLowest(d, tableSize, sample.corner[corner], 3);
      if (sample.window[corner].holdsAll) count = 0;
    }
  }
  return sample;
}

// The four coefficients of ReadVolumeToward (sky_light.cpp) per lane, before their dot product: the
// cells' values broadcast (one cell, or a few selected by lane), from a window of the table (lanes in
// cells side by side along x, GatherWindow in core/math-inl.h), or gathered. The same values on every
// path, so the same bits.
template <class D>
struct VolumeValueV {
  hn::Vec<D> k[4];
  // k0 + k.w towards a direction per lane, left to right.
  hn::Vec<D> Toward(const Vec3V<D>& w) const {
    return hn::Add(hn::Add(hn::Add(k[0], hn::Mul(k[1], w.x)), hn::Mul(k[2], w.y)), hn::Mul(k[3], w.z));
  }
};

template <class D>
VolumeValueV<D> InterpolateVolumeV(D d, const float* table, const VolumeSampleV<D>& sample) {
  const hn::RebindToSigned<D> di;
  hn::Vec<D> t[4][8];  // coefficient k of corner i
  for (int i = 0; i < 8; ++i) {
    if (sample.oneCell) {
      const int32_t index = hn::GetLane(sample.corner[i]);
      for (int k = 0; k < 4; ++k) t[k][i] = hn::Set(d, table[index + k]);
      continue;
    }
    if (const int cells = sample.cells[i]; cells > 0) {
      for (int k = 0; k < 4; ++k) {
        t[k][i] = hn::Set(d, table[sample.cell[i][0] + k]);
        for (int j = 1; j < cells; ++j)
          t[k][i] = hn::IfThenElse(sample.in[i][j], hn::Set(d, table[sample.cell[i][j] + k]), t[k][i]);
      }
      continue;
    }
    const GatherWindow<D>& window = sample.window[i];
    if (window.holdsAll) {
      const auto values = hn::LoadU(d, table + window.first);
      for (int k = 0; k < 4; ++k)
        t[k][i] = hn::TableLookupLanes(values, hn::IndicesFromVec(d, hn::Add(window.place, hn::Set(di, k))));
    } else {
      for (int k = 0; k < 4; ++k) t[k][i] = hn::GatherIndex(d, table, hn::Add(sample.corner[i], hn::Set(di, k)));
    }
  }
  const auto one = hn::Set(d, 1.0f);
  const auto lerp = [&](hn::Vec<D> a, hn::Vec<D> b, hn::Vec<D> w) {
    return hn::Add(hn::Mul(a, hn::Sub(one, w)), hn::Mul(b, w));
  };
  const hn::Vec<D>* f = sample.f;
  VolumeValueV<D> v;
  for (int k = 0; k < 4; ++k) {
    const auto x00 = lerp(t[k][0], t[k][1], f[0]), x10 = lerp(t[k][2], t[k][3], f[0]);
    const auto x01 = lerp(t[k][4], t[k][5], f[0]), x11 = lerp(t[k][6], t[k][7], f[0]);
    v.k[k] = lerp(lerp(x00, x10, f[1]), lerp(x01, x11, f[1]), f[2]);
  }
  return v;
}

void SkyLightKernel(const SkyLightContext& context, const float* srgbDecode, const SkyLightRow& row, size_t y,
                    int width) {
  const DF d;
  const DU du;
  const glm::mat4& m = context.viewToWorld;
  const Vec3V<DF> m0 = Set3(d, glm::vec3(m[0])), m1 = Set3(d, glm::vec3(m[1])), m2 = Set3(d, glm::vec3(m[2]));
  const Vec3V<DF> m3 = Set3(d, glm::vec3(m[3]));
  const auto rayY = hn::Set(d, context.rays.y[y]);
  const auto one = hn::Set(d, 1.0f);
  const Vec3V<DF> constant = Set3(d, context.environment.constantRadiance);
  for (size_t x = 0; x < size_t(width); x += hn::Lanes(d)) {
    const size_t count = size_t(width);
    const auto depth = UnpackDepthV(d, LoadRow(du, row.word2, x, count, PackDepth(kBackgroundDepth)));
    const auto background = hn::Eq(depth, hn::Set(d, kBackgroundDepth));
    const Vec3V<DF> direct = LoadRow3(d, row.direct, x, count);
    Vec3V<DF> diffuse{hn::Zero(d), hn::Zero(d), hn::Zero(d)};
    hn::Vec<DF> reflected[3] = {hn::Zero(d), hn::Zero(d), hn::Zero(d)};
    auto visibility = one;
    if (!hn::AllTrue(d, background)) {
      const auto word0 = LoadRow(du, row.word0, x, count, 0u);
      const auto word1 = LoadRow(du, row.word1, x, count, 0u);
      const Vec3V<DF> viewNormal = UnpackNormalV(d, word1, context.normalEncoding);
      const Vec3V<DF> normal = Add3(Add3(Scale3(m0, viewNormal.x), Scale3(m1, viewNormal.y)), Scale3(m2, viewNormal.z));
      // Where a lane is background its depth is +inf: what it computes is replaced below.
      const auto safeDepth = hn::IfThenElse(background, one, depth);
      const Vec3V<DF> viewPosition{hn::Mul(LoadRow(d, context.rays.x.data(), x, count, 0.0f), safeDepth),
                                   hn::Mul(rayY, safeDepth), hn::Neg(safeDepth)};
      const Vec3V<DF> position =
          Add3(Add3(Add3(Scale3(m0, viewPosition.x), Scale3(m1, viewPosition.y)), Scale3(m2, viewPosition.z)), m3);
      Vec3V<DF> interreflected{hn::Zero(d), hn::Zero(d), hn::Zero(d)};
      if (context.visibility) {
        const VolumeSampleV<DF> sample = SampleVolumeV(d, *context.visibility, position, normal);
        visibility = ClampStd(InterpolateVolumeV(d, context.visibility->coefficients.data(), sample).Toward(normal),
                              hn::Zero(d), one);
        if (context.interreflection) {
          const Vec3V<DF> toViewer =
              Normalize3(d, Vec3V<DF>{hn::Neg(LoadRow(d, context.rays.x.data(), x, count, 0.0f)), hn::Neg(rayY), one});
          const Vec3V<DF> viewMirror =
              Sub3(Scale3(viewNormal, hn::Mul(hn::Set(d, 2.0f), Dot3(viewNormal, toViewer))), toViewer);
          const Vec3V<DF> mirror =
              Add3(Add3(Scale3(m0, viewMirror.x), Scale3(m1, viewMirror.y)), Scale3(m2, viewMirror.z));
          hn::Vec<DF>* channel[3] = {&interreflected.x, &interreflected.y, &interreflected.z};
          for (int c = 0; c < 3; ++c) {
            const VolumeValueV<DF> value =
                InterpolateVolumeV(d, context.interreflection->coefficients[size_t(c)].data(), sample);
            *channel[c] = MaxStd(value.Toward(normal), hn::Zero(d));
            reflected[c] = MaxStd(value.Toward(mirror), hn::Zero(d));
          }
        }
      }
      const Vec3V<DF> irradiance =
          context.environment.constant ? constant : EnvironmentIrradianceV(d, context.environment.irradianceSh, normal);
      const auto metallic = UnpackMetallicV(d, word0);
      const Vec3V<DF> albedo = Scale3(UnpackAlbedoV(d, word0, srgbDecode), hn::Sub(one, metallic));
      diffuse = Scale3(Mul3(albedo, irradiance), visibility);
      if (context.interreflection) diffuse = Add3(diffuse, Mul3(albedo, interreflected));
      diffuse = IfThenElse3(background, Vec3V<DF>{hn::Zero(d), hn::Zero(d), hn::Zero(d)}, diffuse);
      for (hn::Vec<DF>& channel : reflected) channel = hn::IfThenElse(background, hn::Zero(d), channel);
      visibility = hn::IfThenElse(background, one, visibility);
    }
    Vec3V<DF> lit = Add3(direct, diffuse);
    if (!context.environment.constant && !hn::AllFalse(d, background)) {
      const Vec3V<DF> ray =
          Normalize3(d, Vec3V<DF>{LoadRow(d, context.rays.x.data(), x, count, 0.0f), rayY, hn::Set(d, -1.0f)});
      const Vec3V<DF> direction = Add3(Add3(Scale3(m0, ray.x), Scale3(m1, ray.y)), Scale3(m2, ray.z));
      lit = IfThenElse3(background, EnvironmentRadianceV(d, context.environment, direction), lit);
    }
    StoreRow3(diffuse, d, row.diffuse, x, count);
    StoreRow(visibility, d, row.visibility, x, count);
    if (row.reflected[0])
      for (int c = 0; c < 3; ++c) StoreRow(reflected[c], d, row.reflected[c], x, count);
    StoreRow3(lit, d, row.lit, x, count);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(SkyLightKernel);

void SkyLightRowSimd(const SkyLightContext& context, const SkyLightRow& row, size_t y, int width) {
  HWY_DYNAMIC_DISPATCH(SkyLightKernel)(context, SrgbDecodeTableForKernels(), row, y, width);
}

}  // namespace ssgi
#endif
