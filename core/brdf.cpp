#include "core/brdf.h"

#include <cstdint>

namespace ssgi {
namespace {

// BuildDfgTable's output as shipped: integrating it takes about 35 ms (a million cos and pow), which
// every process would otherwise pay at its first composite, and the shipped bits depend on no libm.
// tests/core/brdf_test.cpp checks it against BuildDfgTable bit for bit (and rewrites it with
// SSGI_UPDATE_GOLDEN=1 after an intended change).
constexpr float kShippedDfgTable[2 * kDfgSize * kDfgSize] = {
#include "core/dfg_table.inc"
};

// Van der Corput radical inverse in base 2: the Hammersley set's second coordinate.
double RadicalInverse(uint32_t bits) {
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return double(bits) * 2.3283064365386963e-10;
}

// Karis 2013, IntegrateBRDF: GGX-sampled half vectors h, l = reflect(-v, h); each sample adds
// V * 4 n.l v.h / n.h (BRDF * n.l / pdf without F) split by Schlick into F0 * (1 - Fc) + Fc.
glm::vec2 IntegrateDfg(double nDotV, double alpha) {
  const double vx = std::sqrt(1.0 - nDotV * nDotV), vz = nDotV;
  const double a2 = alpha * alpha;
  double a = 0.0, b = 0.0;
  for (int i = 0; i < kDfgSamples; ++i) {
    const double u = (double(i) + 0.5) / kDfgSamples;
    const double phi = 2.0 * double(kPi) * RadicalInverse(uint32_t(i));
    const double cosTheta = std::sqrt((1.0 - u) / (1.0 + (a2 - 1.0) * u));
    const double sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
    // v lies in the xz plane, so the half vector's y component enters neither v.h nor l.z.
    const double hx = sinTheta * std::cos(phi), hz = cosTheta;
    const double vDotH = vx * hx + vz * hz;
    const double lz = 2.0 * vDotH * hz - vz;
    if (lz <= 0.0 || vDotH <= 0.0) continue;
    const double ggxV = lz * std::sqrt(nDotV * nDotV * (1.0 - a2) + a2);
    const double ggxL = nDotV * std::sqrt(lz * lz * (1.0 - a2) + a2);
    const double weight = 0.5 / (ggxV + ggxL) * 4.0 * lz * vDotH / hz;
    const double fc = std::pow(1.0 - vDotH, 5.0);
    a += (1.0 - fc) * weight;
    b += fc * weight;
  }
  a /= kDfgSamples;
  b /= kDfgSamples;
  const double sum = a + b;
  if (sum > 1.0) {
    a /= sum;
    b /= sum;
  }
  return glm::vec2(float(a), float(b));
}

}  // namespace

DfgTable BuildDfgTable() {
  DfgTable table;
  // n.v = 0 has no defined view direction in the integral; its row uses a just-positive n.v.
  constexpr double kMinNDotV = 1e-4;
  for (int j = 0; j < kDfgSize; ++j) {
    const double roughness = double(j) / (kDfgSize - 1);
    const double alpha = std::max(roughness * roughness, double(kMinGgxAlpha));
    for (int i = 0; i < kDfgSize; ++i) {
      const double nDotV = std::max(double(i) / (kDfgSize - 1), kMinNDotV);
      table.ab[size_t(j * kDfgSize + i)] = IntegrateDfg(nDotV, alpha);
    }
  }
  return table;
}

glm::vec3 SpecularWeight(glm::vec3 f0, float nDotV, float roughness) {
  const DfgTable& table = ShippedDfgTable();
  const float u = std::clamp(nDotV, 0.0f, 1.0f) * (kDfgSize - 1);
  const float v = std::clamp(roughness, 0.0f, 1.0f) * (kDfgSize - 1);
  const int i0 = std::min(int(u), kDfgSize - 2), j0 = std::min(int(v), kDfgSize - 2);
  const float fu = u - float(i0), fv = v - float(j0);
  const auto at = [&](int i, int j) { return table.ab[size_t(j * kDfgSize + i)]; };
  const glm::vec2 top = at(i0, j0) + (at(i0 + 1, j0) - at(i0, j0)) * fu;
  const glm::vec2 bottom = at(i0, j0 + 1) + (at(i0 + 1, j0 + 1) - at(i0, j0 + 1)) * fu;
  const glm::vec2 ab = top + (bottom - top) * fv;
  return f0 * ab.x + glm::vec3(ab.y);
}

const DfgTable& ShippedDfgTable() {
  static const DfgTable table = [] {
    DfgTable t;
    for (size_t k = 0; k < t.ab.size(); ++k) t.ab[k] = {kShippedDfgTable[2 * k], kShippedDfgTable[2 * k + 1]};
    return t;
  }();
  return table;
}

const float* DfgTableForKernels() {
  static const std::array<float, 2 * kDfgSize * kDfgSize> planes = [] {
    const DfgTable& table = ShippedDfgTable();
    std::array<float, 2 * kDfgSize * kDfgSize> split;
    for (size_t k = 0; k < table.ab.size(); ++k) {
      split[k] = table.ab[k].x;
      split[table.ab.size() + k] = table.ab[k].y;
    }
    return split;
  }();
  return planes.data();
}

}  // namespace ssgi
