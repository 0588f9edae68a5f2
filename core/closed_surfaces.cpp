#include "core/closed_surfaces.h"

#include <algorithm>
#include <array>
#include <bit>
#include <numeric>

namespace ssgi {
namespace {

// Union-find over triangles; the smaller index becomes the root, so the parts do not depend on the
// order the edges are joined in.
class Parts {
 public:
  explicit Parts(size_t count) : parent_(count) { std::iota(parent_.begin(), parent_.end(), uint32_t(0)); }
  uint32_t Find(uint32_t t) {
    while (parent_[t] != t) t = parent_[t] = parent_[parent_[t]];
    return t;
  }
  void Join(uint32_t a, uint32_t b) {
    a = Find(a);
    b = Find(b);
    if (a < b) parent_[b] = a;
    if (b < a) parent_[a] = b;
  }
  // Every triangle's root, in one pass: a parent never has a larger index than its child.
  std::vector<uint32_t> Roots() const {
    std::vector<uint32_t> roots(parent_.size());
    for (size_t t = 0; t < roots.size(); ++t) roots[t] = parent_[t] == t ? uint32_t(t) : roots[parent_[t]];
    return roots;
  }

 private:
  std::vector<uint32_t> parent_;
};

// Per vertex: an index shared by every vertex at the same position (the same bits).
std::vector<uint32_t> WeldPositions(const std::vector<glm::vec3>& positions) {
  using Bits = std::array<uint32_t, 3>;
  const auto bits = [&](uint32_t v) {
    const glm::vec3& p = positions[v];
    return Bits{std::bit_cast<uint32_t>(p.x), std::bit_cast<uint32_t>(p.y), std::bit_cast<uint32_t>(p.z)};
  };
  std::vector<uint32_t> order(positions.size());
  std::iota(order.begin(), order.end(), uint32_t(0));
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return bits(a) < bits(b); });
  std::vector<uint32_t> welded(positions.size());
  for (size_t i = 0; i < order.size(); ++i)
    welded[order[i]] = i > 0 && bits(order[i]) == bits(order[i - 1]) ? welded[order[i - 1]] : order[i];
  return welded;
}

// A triangle's edge, filed under its smaller welded end.
struct Edge {
  uint32_t larger;  // the other welded end
  uint32_t triangle;
  bool ascending;  // the triangle runs from the smaller end to the larger
};

}  // namespace

size_t ClosedSurfacesBuildBytes(size_t triangles, size_t vertices) {
  // Per vertex: the sort order, the joined index, and the edges' first and next places. Per
  // triangle: three edges, the open flags, the parts and their roots, the part's flag and volume,
  // the result's index and a part's surface index, and at most a quarter of a surface's box (a
  // closed surface has at least four triangles).
  const size_t perTriangle = 3 * sizeof(Edge) + 2 * sizeof(uint8_t) + 4 * sizeof(uint32_t) + sizeof(double) +
                             2 * sizeof(glm::vec3) / 4 + sizeof(uint32_t);
  return 4 * sizeof(uint32_t) * vertices + perTriangle * triangles;
}

ClosedSurfaces FindClosedSurfaces(const Mesh& mesh) {
  const size_t triangles = mesh.TriangleCount();
  const std::vector<uint32_t> welded = WeldPositions(mesh.positions);
  const auto corners = [&](size_t t) {
    return std::array<uint32_t, 3>{welded[mesh.indices[3 * t]], welded[mesh.indices[3 * t + 1]],
                                   welded[mesh.indices[3 * t + 2]]};
  };
  // The edges filed by their smaller end (a counting sort, in triangle order), then each end's few
  // edges sorted by the other end: equal edges side by side without sorting them all.
  std::vector<uint32_t> first(mesh.positions.size() + 1, 0);
  for (size_t t = 0; t < triangles; ++t) {
    const std::array<uint32_t, 3> c = corners(t);
    for (int e = 0; e < 3; ++e) ++first[std::min(c[e], c[(e + 1) % 3]) + 1];
  }
  for (size_t v = 1; v < first.size(); ++v) first[v] += first[v - 1];
  std::vector<Edge> edges(3 * triangles);
  std::vector<uint32_t> next(first.begin(), first.end() - 1);
  std::vector<uint8_t> open(triangles, 0);
  for (size_t t = 0; t < triangles; ++t) {
    const std::array<uint32_t, 3> c = corners(t);
    if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0]) open[t] = 1;
    for (int e = 0; e < 3; ++e) {
      const uint32_t from = c[e], to = c[(e + 1) % 3];
      edges[next[std::min(from, to)]++] = {std::max(from, to), uint32_t(t), from < to};
    }
  }
  Parts parts(triangles);
  for (size_t v = 0; v + 1 < first.size(); ++v) {
    const auto begin = edges.begin() + first[v], end = edges.begin() + first[v + 1];
    std::sort(begin, end, [](const Edge& a, const Edge& b) {
      return a.larger != b.larger ? a.larger < b.larger : a.triangle < b.triangle;
    });
    for (auto i = begin; i != end;) {
      auto j = i + 1;
      while (j != end && j->larger == i->larger) ++j;
      for (auto k = i + 1; k != j; ++k) parts.Join(i->triangle, k->triangle);
      const bool manifold = j - i == 2 && i->ascending != (i + 1)->ascending;
      if (!manifold)
        for (auto k = i; k != j; ++k) open[k->triangle] = 1;
      i = j;
    }
  }

  // A part is closed when none of its triangles is open and it encloses a positive volume (its front
  // faces outside): a closed part turned inside out, as a room modelled from within, is seen through
  // its back faces first. The volume is the sum of the signed tetrahedra from the part's first
  // vertex (its root triangle's first corner), in double and in triangle order.
  const std::vector<uint32_t> roots = parts.Roots();
  std::vector<uint8_t> partOpen(triangles, 0);
  std::vector<double> volume(triangles, 0.0);
  const auto corner = [&](size_t t, int k) { return glm::dvec3(mesh.positions[mesh.indices[3 * t + size_t(k)]]); };
  for (size_t t = 0; t < triangles; ++t) {
    const uint32_t root = roots[t];
    partOpen[root] |= open[t];
    const glm::dvec3 origin = corner(root, 0);
    volume[root] += glm::dot(corner(t, 0) - origin, glm::cross(corner(t, 1) - origin, corner(t, 2) - origin));
  }

  ClosedSurfaces out;
  out.meshHash = MeshGeometryHash(mesh);
  out.surface.assign(triangles, ClosedSurfaces::kOpen);
  std::vector<uint32_t> surfaceOfRoot(triangles, ClosedSurfaces::kOpen);
  for (size_t t = 0; t < triangles; ++t) {
    const uint32_t root = roots[t];
    if (partOpen[root] || !(volume[root] > 0.0)) continue;
    if (surfaceOfRoot[root] == ClosedSurfaces::kOpen) {
      surfaceOfRoot[root] = uint32_t(out.lo.size());
      out.lo.push_back(mesh.positions[mesh.indices[3 * t]]);
      out.hi.push_back(out.lo.back());
    }
    const uint32_t s = out.surface[t] = surfaceOfRoot[root];
    for (int k = 0; k < 3; ++k) {
      out.lo[s] = glm::min(out.lo[s], mesh.positions[mesh.indices[3 * t + k]]);
      out.hi[s] = glm::max(out.hi[s], mesh.positions[mesh.indices[3 * t + k]]);
    }
  }
  return out;
}

}  // namespace ssgi
