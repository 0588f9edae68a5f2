#include "core/mesh.h"

#include <cstring>

namespace ssgi {

uint64_t MeshGeometryHash(const Mesh& mesh) {
  // Every frame checks it: four independent FNV-1a chains over the 64-bit words (word i into chain
  // i mod 4), so the multiplies overlap, folded together at the end.
  constexpr uint64_t kPrime = 1099511628211ull;
  uint64_t chain[4] = {1469598103934665603ull, 1469598103934665603ull ^ 1, 1469598103934665603ull ^ 2,
                       1469598103934665603ull ^ 3};
  const auto add = [&](const void* data, size_t bytes) {
    const auto* p = static_cast<const uint8_t*>(data);
    size_t i = 0;
    for (; i + 32 <= bytes; i += 32) {
      uint64_t words[4];
      std::memcpy(words, p + i, 32);
      for (int k = 0; k < 4; ++k) chain[k] = (chain[k] ^ words[k]) * kPrime;
    }
    for (; i < bytes; ++i) chain[0] = (chain[0] ^ p[i]) * kPrime;
    chain[1] = (chain[1] ^ bytes) * kPrime;
  };
  add(mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
  add(mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
  uint64_t hash = chain[0];
  for (int k = 1; k < 4; ++k) hash = (hash ^ chain[k]) * kPrime;
  return hash;
}

}  // namespace ssgi
