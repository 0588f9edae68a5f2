#include "passes/world_bounce.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/check.h"
#include "core/parallel.h"
#include "core/reference/ray_tracer.h"
#include "core/reference/reference.h"
#include "passes/shadow_map.h"

namespace ssgi {
namespace {

// Cell `cell`'s (x, y, z) in the grid (x fastest, then y, then z).
glm::ivec3 CellCoordinates(const SkyVisibilityVolume& grid, size_t cell) {
  return {int(cell % size_t(grid.cellsX)), int(cell / size_t(grid.cellsX) % size_t(grid.cellsY)),
          int(cell / (size_t(grid.cellsX) * size_t(grid.cellsY)))};
}

glm::vec3 CellCentre(const SkyVisibilityVolume& grid, size_t cell) {
  return grid.origin + (glm::vec3(CellCoordinates(grid, cell)) + 0.5f) * grid.cellSize;
}

// 1 for each cell within `margin` cells of a triangle's bounds.
std::vector<uint8_t> CellsNearSurfaces(const Scene& scene, const SkyVisibilityVolume& grid, int margin) {
  std::vector<uint8_t> near(grid.coefficients.size() / 4, 0);
  const int cells[3] = {grid.cellsX, grid.cellsY, grid.cellsZ};
  for (size_t t = 0; t < scene.mesh.TriangleCount(); ++t) {
    glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
    for (int v = 0; v < 3; ++v) {
      const glm::vec3& p = scene.mesh.positions[scene.mesh.indices[3 * t + size_t(v)]];
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    int first[3], last[3];
    for (int a = 0; a < 3; ++a) {
      first[a] = std::max(int(std::floor((lo[a] - grid.origin[a]) * grid.inverseCellSize)) - margin, 0);
      last[a] = std::min(int(std::floor((hi[a] - grid.origin[a]) * grid.inverseCellSize)) + margin, cells[a] - 1);
    }
    for (int z = first[2]; z <= last[2]; ++z)
      for (int y = first[1]; y <= last[1]; ++y)
        std::fill_n(
            near.begin() + ptrdiff_t((size_t(z) * size_t(grid.cellsY) + size_t(y)) * size_t(grid.cellsX)) + first[0],
            std::max(last[0] - first[0] + 1, 0), uint8_t(1));
  }
  return near;
}

// Each read cell inside a wall takes the mean of its face neighbours that are read and not inside
// (from the values before the fill, so the order of cells does not matter); one with none keeps 0.
void FillInsideCells(const SkyVisibilityVolume& grid, const std::vector<uint8_t>& read,
                     const std::vector<uint8_t>& inside, WorldBounceVolume& volume) {
  const std::array<std::vector<float>, 3> before = volume.coefficients;
  const int cells[3] = {grid.cellsX, grid.cellsY, grid.cellsZ};
  const ptrdiff_t stride[3] = {1, grid.cellsX, ptrdiff_t(grid.cellsX) * grid.cellsY};
  ParallelFor("world_bounce.fill", inside.size(), [&](size_t cell) {
    if (!read[cell] || !inside[cell]) return;
    const glm::ivec3 position = CellCoordinates(grid, cell);
    float sum[3][4] = {};
    int count = 0;
    for (int a = 0; a < 3; ++a)
      for (int side : {-1, 1}) {
        const int p = position[a] + side;
        if (p < 0 || p >= cells[a]) continue;
        const size_t neighbour = size_t(ptrdiff_t(cell) + side * stride[a]);
        if (!read[neighbour] || inside[neighbour]) continue;
        ++count;
        for (int c = 0; c < 3; ++c)
          for (int j = 0; j < 4; ++j) sum[c][j] += before[size_t(c)][neighbour * 4 + size_t(j)];
      }
    if (count == 0) return;
    for (int c = 0; c < 3; ++c)
      for (int j = 0; j < 4; ++j) volume.coefficients[size_t(c)][cell * 4 + size_t(j)] = sum[c][j] / float(count);
  });
}

bool SameLight(const PreparedLight& a, const PreparedLight& b) {
  return a.isSpot == b.isSpot && a.position == b.position && a.direction == b.direction && a.power == b.power &&
         a.tanAngularRadius == b.tanAngularRadius && a.radius == b.radius && a.cosOuter == b.cosOuter &&
         a.coneScale == b.coneScale;
}

}  // namespace

WorldBounceVolume EmptyWorldBounce(const Scene& scene, const SkyVisibilityVolume& sky, const Environment& environment,
                                   const WorldBounceParams& params) {
  WorldBounceVolume volume;
  volume.meshHash = sky.meshHash;
  volume.lights = PrepareLights(scene, glm::mat4(1.0f));
  volume.environment = environment;
  volume.grid = sky.params;
  volume.params = params;
  for (std::vector<float>& channel : volume.coefficients) channel.assign(sky.coefficients.size(), 0.0f);
  return volume;
}

WorldBounceVolume BuildWorldBounce(const Scene& scene, const SkyVisibilityVolume& sky,
                                   const EnvironmentLighting& environment, const WorldBounceParams& params) {
  SSGI_CHECK(params.directions > 0);
  WorldBounceVolume volume = EmptyWorldBounce(scene, sky, environment.source, params);
  const size_t cells = sky.coefficients.size() / 4;
  if (scene.mesh.TriangleCount() == 0) return volume;

  const RayTracer tracer(scene);
  const float offset = RayOffset(scene);
  std::vector<bool> casts(volume.lights.size(), false);
  for (const size_t light : ShadowCastingLights(scene)) casts[light] = true;
  const std::vector<glm::vec3> directions = SkyVisibilityDirections(params.directions);
  const float share = 1.0f / float(directions.size());
  constexpr float kInfinity = std::numeric_limits<float>::infinity();
  // The radiance leaving the surface a ray from a cell hits, towards the cell: diffuse only (the
  // volume is a diffuse term), from every light and the sky. `back`: the ray met the back of a
  // one-sided surface (light from there would come through it).
  const auto radianceTowards = [&](const glm::vec3& direction, const Hit& hit, glm::vec3& diffuseAlbedo,
                                   bool& back) -> glm::vec3 {
    const uint32_t* idx = &scene.mesh.indices[3 * size_t(hit.triangle)];
    const Material& material = scene.materials[scene.mesh.materials[hit.triangle]];
    back = !material.twoSided && glm::dot(FaceNormal(scene.mesh, idx), direction) > 0.0f;
    if (back) return glm::vec3(0.0f);
    const RaySurface s = ResolveRaySurface(scene, hit, direction);
    diffuseAlbedo = s.material.albedo * (1.0f - s.material.metallic);
    const glm::vec3 from = s.position + s.faceNormal * offset;
    glm::vec3 irradiance(0.0f);
    for (size_t i = 0; i < volume.lights.size(); ++i) {
      const PreparedLight& light = volume.lights[i];
      const LightAtPoint at = Evaluate(light, s.position);
      const float cosine = glm::dot(s.normal, at.toLight);
      if (!(cosine > 0.0f)) continue;
      if (casts[i]) {
        const float distance = light.isSpot ? glm::length(light.position - s.position) : kInfinity;
        if (tracer.Occluded(from, at.toLight, 0.0f, distance)) continue;
      }
      irradiance += at.irradiance * cosine;
    }
    const glm::vec3 skyLight = EnvironmentIrradiance(environment, s.normal) * SkyVisibility(sky, s.position, s.normal);
    return diffuseAlbedo * (irradiance * (1.0f / kPi) + skyLight);
  };

  // Only the cells a surface point can read (SampleVolume: the eight around p + n cellSize / 2) are
  // made: those within two cells of a triangle's bounds. The rest stay 0 and are never read.
  const std::vector<uint8_t> read = CellsNearSurfaces(scene, sky, 2);
  // Rays that see the back of a one-sided surface from a cell: the cell lies inside a wall, where
  // its light (0) is no light the wall's surface receives. Such cells take their neighbours'.
  std::vector<uint8_t> inside(cells, 0);
  ParallelFor("world_bounce.cells", cells, [&](size_t cell) {
    if (!read[cell]) return;
    const glm::vec3 centre = CellCentre(sky, cell);
    glm::vec3 k[4] = {glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f)};
    glm::vec3 albedoSum(0.0f);
    int hits = 0, backHits = 0;
    for (const glm::vec3& direction : directions) {
      Hit hit;
      if (!tracer.Intersect(RayKind::kBothFaces, centre, direction, 0.0f, kInfinity, hit)) continue;
      ++hits;
      glm::vec3 diffuseAlbedo(0.0f);
      bool back = false;
      const glm::vec3 radiance = radianceTowards(direction, hit, diffuseAlbedo, back);
      if (back) {
        ++backHits;
        continue;
      }
      albedoSum += diffuseAlbedo;
      // As the visibility volume: k0 = mean(L), (kx, ky, kz) = 2 mean(L w).
      k[0] += radiance * share;
      k[1] += radiance * (2.0f * share * direction.x);
      k[2] += radiance * (2.0f * share * direction.y);
      k[3] += radiance * (2.0f * share * direction.z);
    }
    inside[cell] = backHits * kWorldBounceInsideShare > int(directions.size());
    const float blocked = float(hits) * share;
    for (int c = 0; c < 3; ++c) {
      const float meanAlbedo = hits > backHits ? albedoSum[c] / float(hits - backHits) : 0.0f;
      const float again = 1.0f / (1.0f - std::min(meanAlbedo * blocked, kWorldBounceMaxReflected));
      for (int j = 0; j < 4; ++j) volume.coefficients[size_t(c)][cell * 4 + size_t(j)] = k[j][c] * again;
    }
  });
  FillInsideCells(sky, read, inside, volume);
  return volume;
}

bool WorldBounceHolds(const WorldBounceVolume& volume, const Scene& scene, const SkyVisibilityVolume& sky,
                      const EnvironmentLighting& environment, const WorldBounceParams& params) {
  const std::vector<PreparedLight> lights = PrepareLights(scene, glm::mat4(1.0f));
  return volume.meshHash == sky.meshHash && volume.params.directions == params.directions &&
         volume.grid.cellsOnLongestAxis == sky.params.cellsOnLongestAxis &&
         volume.coefficients[0].size() == sky.coefficients.size() && volume.environment.Same(environment.source) &&
         std::equal(lights.begin(), lights.end(), volume.lights.begin(), volume.lights.end(), SameLight);
}

size_t WorldBounceBytes(const Scene& scene, const SkyVisibilityParams& grid, const WorldBounceParams& params) {
  if (params.directions == 0 || grid.directions == 0) return 0;
  return 3 * SkyVisibilityBytes(scene, grid);
}

size_t WorldBounceBuildBytes(const Scene& scene, const SkyVisibilityParams& grid, const WorldBounceParams& params) {
  const size_t coefficients = WorldBounceBytes(scene, grid, params);
  if (coefficients == 0) return 0;
  const size_t cells = coefficients / (3 * 4 * sizeof(float));
  return kReferenceBvhBytesPerTriangle * scene.mesh.TriangleCount() + 2 * cells + coefficients;
}

}  // namespace ssgi
