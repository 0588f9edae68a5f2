#include "passes/sky_light.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/check.h"
#include "core/parallel.h"
#include "core/raster/raster.h"
#include "core/raster/scene_raster_input.h"
#include "core/stopwatch.h"
#include "passes/world_bounce.h"

namespace ssgi {
namespace {

// Whether each cell centre sees the sky along `toSky`: the scene rasterized along -toSky over its
// bounding sphere, a cell visible when nothing drawn lies nearer the sky than it (by more than half
// a cell, so the surface a cell centre lies on does not hide it).
std::vector<uint8_t> CellsSeeingSky(const Scene& scene, const SkyVisibilityVolume& volume, const glm::vec3& toSky,
                                    const glm::vec3& centre, float radius) {
  const int size = volume.params.mapSize;
  const glm::vec3 forward = -toSky;
  const ViewProjection map =
      MakeOrthographic(centre - forward * (radius * 1.01f), forward, UpHint(forward), radius, radius, 0.0f,
                       2.02f * radius, size, size);
  const SceneRasterInput raster(scene, map, false);
  VisibilityBuffer target = MakeVisibilityBuffer(size, size, RasterOutput::kDepthOnly);
  Rasterize(raster.Get(), map, RasterOutput::kDepthOnly, target);
  const float bias = 0.5f * volume.cellSize;
  std::vector<uint8_t> visible(volume.coefficients.size() / 4, 1);
  size_t cell = 0;
  for (int z = 0; z < volume.cellsZ; ++z)
    for (int y = 0; y < volume.cellsY; ++y)
      for (int x = 0; x < volume.cellsX; ++x, ++cell) {
        const glm::vec3 p = volume.origin + (glm::vec3(float(x), float(y), float(z)) + 0.5f) * volume.cellSize;
        const glm::vec4 v = map.view * glm::vec4(p, 1.0f);
        const float px = (v.x / map.halfX + 1.0f) * 0.5f * float(size);
        const float py = (1.0f - v.y / map.halfY) * 0.5f * float(size);
        if (!(px >= 0.0f && px < float(size) && py >= 0.0f && py < float(size))) continue;
        const float key = target.depthKey.ConstRow(size_t(py))[size_t(px)];
        if (key > 0.0f && map.DepthFromKey(key) + bias < -v.z) visible[cell] = 0;
      }
  return visible;
}

}  // namespace

SkyVisibilityVolume SkyVisibilityGrid(const Scene& scene, const SkyVisibilityParams& params) {
  SSGI_CHECK(params.directions > 0 && params.mapSize > 0 && params.cellsOnLongestAxis > 0);
  SkyVisibilityVolume volume;
  volume.params = params;
  glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (const glm::vec3& p : scene.mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  if (scene.mesh.positions.empty()) lo = hi = glm::vec3(0.0f);
  volume.extent = hi - lo;
  const float longest = std::max({volume.extent.x, volume.extent.y, volume.extent.z, 1e-3f});
  volume.cellSize = longest / float(params.cellsOnLongestAxis);
  volume.inverseCellSize = 1.0f / volume.cellSize;
  volume.origin = lo - volume.cellSize;
  volume.cellsX = int(std::ceil(volume.extent.x * volume.inverseCellSize)) + 2;
  volume.cellsY = int(std::ceil(volume.extent.y * volume.inverseCellSize)) + 2;
  volume.cellsZ = int(std::ceil(volume.extent.z * volume.inverseCellSize)) + 2;
  return volume;
}

std::vector<glm::vec3> SkyVisibilityDirections(int count) {
  constexpr double kGoldenAngle = 2.39996322972865332;
  std::vector<glm::vec3> directions;
  for (int i = 0; i < count; ++i) {
    const double y = 1.0 - 2.0 * (double(i) + 0.5) / double(count);
    const double r = std::sqrt(std::max(0.0, 1.0 - y * y));
    const double phi = kGoldenAngle * double(i);
    directions.emplace_back(float(r * std::cos(phi)), float(y), float(r * std::sin(phi)));
  }
  return directions;
}

size_t SkyVisibilityBytes(const Scene& scene, const SkyVisibilityParams& params) {
  if (params.directions == 0) return 0;
  const SkyVisibilityVolume grid = SkyVisibilityGrid(scene, params);
  return size_t(grid.cellsX) * size_t(grid.cellsY) * size_t(grid.cellsZ) * 4 * sizeof(float);
}

size_t SkyVisibilityBuildBytes(const Scene& scene, const SkyVisibilityParams& params) {
  if (params.directions == 0) return 0;
  const SkyVisibilityVolume grid = SkyVisibilityGrid(scene, params);
  const size_t cells = size_t(grid.cellsX) * size_t(grid.cellsY) * size_t(grid.cellsZ);
  // What the rasterizer keeps per triangle (its set-up and bins) and the scene's raster input.
  constexpr size_t kRasterBytesPerTriangle = 168;
  const size_t map = hwy::ImageBase::BytesPerRow(size_t(params.mapSize), sizeof(float)) * size_t(params.mapSize);
  const size_t perThread = map + kRasterBytesPerTriangle * scene.mesh.TriangleCount();
  return size_t(std::min(HardwareThreads(), params.directions)) * perThread + size_t(params.directions) * cells;
}

SkyVisibilityVolume BuildSkyVisibility(const Scene& scene, const SkyVisibilityParams& params) {
  SkyVisibilityVolume volume = SkyVisibilityGrid(scene, params);
  const size_t cells = size_t(volume.cellsX) * size_t(volume.cellsY) * size_t(volume.cellsZ);
  volume.coefficients.assign(cells * 4, 0.0f);
  volume.meshHash = MeshGeometryHash(scene.mesh);
  const glm::vec3 lo = volume.origin + volume.cellSize, hi = lo + volume.extent;
  const glm::vec3 extent = volume.extent;
  const glm::vec3 centre = (lo + hi) * 0.5f;
  const float radius = std::max(0.5f * glm::length(extent), 1e-3f) + volume.cellSize;
  const std::vector<glm::vec3> directions = SkyVisibilityDirections(params.directions);
  std::vector<std::vector<uint8_t>> visible(directions.size());
  ParallelFor("sky_visibility.maps", directions.size(), [&](size_t i) {
    visible[i] = CellsSeeingSky(scene, volume, directions[i], centre, radius);
  });
  // The clamped-cosine convolution of the visibility in the first two SH bands, with the directions
  // as an equal-weight quadrature: k0 = mean(v), (kx, ky, kz) = 2 mean(v w) (Y00^2 4 pi = 1 and
  // 2/3 * 3 / (4 pi) * 4 pi = 2).
  const float share = 1.0f / float(directions.size());
  ParallelFor("sky_visibility.cells", cells, [&](size_t cell) {
    float k[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    for (size_t i = 0; i < directions.size(); ++i) {
      if (!visible[i][cell]) continue;
      k[0] += share;
      k[1] += 2.0f * share * directions[i].x;
      k[2] += 2.0f * share * directions[i].y;
      k[3] += 2.0f * share * directions[i].z;
    }
    std::copy_n(k, 4, &volume.coefficients[cell * 4]);
  });
  return volume;
}

VolumeSample SampleVolume(const SkyVisibilityVolume& volume, const glm::vec3& position, const glm::vec3& normal) {
  const float offset = 0.5f * volume.cellSize;
  const glm::vec3 q = (position + normal * offset - volume.origin) * volume.inverseCellSize - 0.5f;
  const int cells[3] = {volume.cellsX, volume.cellsY, volume.cellsZ};
  int i0[3], i1[3];
  VolumeSample sample;
  for (int a = 0; a < 3; ++a) {
    const float c = std::clamp(q[a], 0.0f, float(cells[a] - 1));
    i0[a] = int(c);
    i1[a] = std::min(i0[a] + 1, cells[a] - 1);
    sample.f[a] = c - float(i0[a]);
  }
  const auto at = [&](int x, int y, int z) {
    return ((size_t(z) * size_t(volume.cellsY) + size_t(y)) * size_t(volume.cellsX) + size_t(x)) * 4;
  };
  for (int corner = 0; corner < 8; ++corner)
    sample.corner[corner] = at(corner & 1 ? i1[0] : i0[0], corner & 2 ? i1[1] : i0[1], corner & 4 ? i1[2] : i0[2]);
  sample.normal = normal;
  return sample;
}

float ReadVolume(const float* coefficients, const VolumeSample& sample) {
  return ReadVolumeToward(coefficients, sample, sample.normal);
}

float ReadVolumeToward(const float* coefficients, const VolumeSample& sample, const glm::vec3& direction) {
  const float* f = sample.f;
  float v[4];
  for (int k = 0; k < 4; ++k) {
    const auto at = [&](int corner) { return coefficients[sample.corner[corner] + size_t(k)]; };
    // x, then y, then z.
    const float x00 = at(0) * (1.0f - f[0]) + at(1) * f[0];
    const float x10 = at(2) * (1.0f - f[0]) + at(3) * f[0];
    const float x01 = at(4) * (1.0f - f[0]) + at(5) * f[0];
    const float x11 = at(6) * (1.0f - f[0]) + at(7) * f[0];
    const float y0 = x00 * (1.0f - f[1]) + x10 * f[1];
    const float y1 = x01 * (1.0f - f[1]) + x11 * f[1];
    v[k] = y0 * (1.0f - f[2]) + y1 * f[2];
  }
  return v[0] + v[1] * direction.x + v[2] * direction.y + v[3] * direction.z;
}

float SkyVisibility(const SkyVisibilityVolume& volume, const glm::vec3& position, const glm::vec3& normal) {
  return std::clamp(ReadVolume(volume.coefficients.data(), SampleVolume(volume, position, normal)), 0.0f, 1.0f);
}

void SkyLightRowScalar(const SkyLightContext& context, const SkyLightRow& row, size_t y, int width) {
  for (int x = 0; x < width; ++x) {
    const float depth = UnpackDepth(row.word2[x]);
    // World space: each row of the matrix products left to right, (m0 a + m1 b) + m2 c (+ m3).
    const glm::mat4& m = context.viewToWorld;
    if (depth == kBackgroundDepth) {
      // The environment itself, seen along the pixel's ray (a constant one is already there).
      glm::vec3 background(row.direct[0][x] + 0.0f, row.direct[1][x] + 0.0f, row.direct[2][x] + 0.0f);
      if (!context.environment.constant) {
        const glm::vec3 ray = glm::normalize(glm::vec3(context.rays.x[size_t(x)], context.rays.y[y], -1.0f));
        const glm::vec3 direction = (glm::vec3(m[0]) * ray.x + glm::vec3(m[1]) * ray.y) + glm::vec3(m[2]) * ray.z;
        background = EnvironmentRadiance(context.environment, direction);
      }
      for (int c = 0; c < 3; ++c) {
        row.diffuse[c][x] = 0.0f;
        row.lit[c][x] = background[c];
      }
      row.visibility[x] = 1.0f;
      if (row.reflected[0])
        for (int c = 0; c < 3; ++c) row.reflected[c][x] = 0.0f;
      continue;
    }
    const glm::vec3 viewNormal = UnpackNormal(row.word1[x], context.normalEncoding);
    const glm::vec3 normal =
        (glm::vec3(m[0]) * viewNormal.x + glm::vec3(m[1]) * viewNormal.y) + glm::vec3(m[2]) * viewNormal.z;
    const glm::vec3 viewPosition(context.rays.x[size_t(x)] * depth, context.rays.y[y] * depth, -depth);
    const glm::vec3 position =
        ((glm::vec3(m[0]) * viewPosition.x + glm::vec3(m[1]) * viewPosition.y) + glm::vec3(m[2]) * viewPosition.z) +
        glm::vec3(m[3]);
    float visibility = 1.0f;
    glm::vec3 interreflected(0.0f);
    if (context.visibility) {
      const VolumeSample sample = SampleVolume(*context.visibility, position, normal);
      visibility = std::clamp(ReadVolume(context.visibility->coefficients.data(), sample), 0.0f, 1.0f);
      if (context.interreflection) {
        // The mirror direction as the composite takes it: r = n (2 n.v) - v in view space, v towards
        // the viewer.
        const glm::vec3 toViewer = glm::normalize(glm::vec3(-context.rays.x[size_t(x)], -context.rays.y[y], 1.0f));
        const glm::vec3 viewMirror = viewNormal * (2.0f * glm::dot(viewNormal, toViewer)) - toViewer;
        const glm::vec3 mirror =
            (glm::vec3(m[0]) * viewMirror.x + glm::vec3(m[1]) * viewMirror.y) + glm::vec3(m[2]) * viewMirror.z;
        for (int c = 0; c < 3; ++c) {
          const float* table = context.interreflection->coefficients[size_t(c)].data();
          interreflected[c] = std::max(ReadVolume(table, sample), 0.0f);
          row.reflected[c][x] = std::max(ReadVolumeToward(table, sample, mirror), 0.0f);
        }
      }
    }
    const glm::vec3 irradiance = EnvironmentIrradiance(context.environment, normal);
    const float metallic = UnpackMetallic(row.word0[x]);
    const glm::vec3 albedo = UnpackAlbedo(row.word0[x]) * (1.0f - metallic);
    for (int c = 0; c < 3; ++c) {
      float diffuse = albedo[c] * irradiance[c] * visibility;
      if (context.interreflection) diffuse = diffuse + albedo[c] * interreflected[c];
      row.diffuse[c][x] = diffuse;
      row.lit[c][x] = row.direct[c][x] + diffuse;
    }
    row.visibility[x] = visibility;
  }
}

SkyLightStats RunSkyLight(const SkyLightInputs& in, const SkyLightParams&, SkyLightOutputs& out, KernelPath kernels) {
  Stopwatch stopwatch;
  const int width = in.gbuffer.width(), height = in.gbuffer.height();
  ReusePlane3(out.diffuse, size_t(width), size_t(height));
  ReusePlane3(out.lit, size_t(width), size_t(height));
  const bool reflected = in.visibility && in.interreflection;
  if (reflected)
    ReusePlane3(out.reflected, size_t(width), size_t(height));
  else
    out.reflected = {};
  if (out.visibility.xsize() != size_t(width) || out.visibility.ysize() != size_t(height))
    out.visibility = MakePlane<float>(size_t(width), size_t(height), 1.0f);
  // The interreflection is read with the visibility volume's cells and windows: the same grid.
  if (in.visibility && in.interreflection)
    for (const std::vector<float>& channel : in.interreflection->coefficients)
      SSGI_CHECK(channel.size() == in.visibility->coefficients.size());
  const PixelRayTables rays = MakePixelRayTables(in.view, size_t(width), size_t(height));
  const SkyLightContext context{glm::inverse(in.view.view),
                                in.gbuffer.normalEncoding,
                                rays,
                                in.environment,
                                in.visibility,
                                in.visibility ? in.interreflection : nullptr};
  const auto kernel = kernels == KernelPath::kSimd ? SkyLightRowSimd : SkyLightRowScalar;
  ParallelForRowBands("sky_light", size_t(height), [&](size_t, size_t yBegin, size_t yEnd) {
    for (size_t y = yBegin; y < yEnd; ++y) {
      const SkyLightRow row{
          in.gbuffer.word[GBufferWord::kAlbedoMetallic].ConstRow(y),
          in.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(y),
          in.gbuffer.word[GBufferWord::kDepth].ConstRow(y),
          {in.direct.c[0].ConstRow(y), in.direct.c[1].ConstRow(y), in.direct.c[2].ConstRow(y)},
          {out.diffuse.c[0].MutableRow(y), out.diffuse.c[1].MutableRow(y), out.diffuse.c[2].MutableRow(y)},
          out.visibility.MutableRow(y),
          {out.lit.c[0].MutableRow(y), out.lit.c[1].MutableRow(y), out.lit.c[2].MutableRow(y)},
          {reflected ? out.reflected.c[0].MutableRow(y) : nullptr,
           reflected ? out.reflected.c[1].MutableRow(y) : nullptr,
           reflected ? out.reflected.c[2].MutableRow(y) : nullptr},
      };
      kernel(context, row, y, width);
    }
  });
  SkyLightStats stats;
  stats.pixels = size_t(width) * size_t(height);
  stats.ms = stopwatch.Lap();
  return stats;
}

}  // namespace ssgi
