#include "tests/port/gl_sky_volume.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/camera.h"

namespace ssgi::port {

Buffer RunPortSkyVolume(const SceneBuffers& scene, const SkyVisibilityVolume& grid) {
  const size_t cells = size_t(grid.cellsX) * size_t(grid.cellsY) * size_t(grid.cellsZ);
  Buffer volume(cells * 4, std::vector<float>(cells * 4, 0.0f).data());
  const int directions = grid.params.directions;
  if (directions <= 0) return volume;
  // The maps' bounding sphere over the mesh's bounds.
  const glm::vec3 lo = grid.origin + grid.cellSize, hi = lo + grid.extent;
  const glm::vec3 centre = (lo + hi) * 0.5f;
  const float radius = std::max(0.5f * glm::length(grid.extent), 1e-3f) + grid.cellSize;
  const int size = grid.params.mapSize;
  const Program program("sky_volume.comp");
  program.Set("cells", grid.cellsX, grid.cellsY, grid.cellsZ);
  program.Set("origin", grid.origin.x, grid.origin.y, grid.origin.z);
  program.Set("cellSize", grid.cellSize);
  program.Set("mapSize", size);
  program.Set("share", 1.0f / float(directions));
  for (const glm::vec3& toSky : SkyVisibilityDirections(directions)) {
    const glm::vec3 forward = -toSky;
    const ViewProjection map = MakeOrthographic(centre - forward * (radius * 1.01f), forward, UpHint(forward), radius,
                                                radius, 0.0f, 2.02f * radius, size, size);
    // Both faces drawn; cut-outs alpha tested along the map's rays, as for the shadow map.
    const VisibilityTargets target = RunVisibilityPass(scene, map, false, RasterKind::kDepthOnly);
    program.SetMatrix("mapView", &map.view[0][0]);
    program.Set("mapHalf", map.halfX, map.halfY);
    program.Set("mapNear", map.nearPlane);
    program.Set("mapFar", map.farPlane);
    program.Set("towardSky", toSky.x, toSky.y, toSky.z);
    target.depthKey.Bind(0);
    volume.Bind(1);
    program.Dispatch(grid.cellsX, grid.cellsY, grid.cellsZ);
  }
  return volume;
}

}  // namespace ssgi::port
