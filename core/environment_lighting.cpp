#include "core/environment_lighting.h"

#include <algorithm>
#include <cmath>

#include "core/brdf.h"
#include "core/check.h"
#include "core/parallel.h"

namespace ssgi {
namespace {

float SignNotZero(float t) { return t >= 0.0f ? 1.0f : -1.0f; }

// Where texel (i, j) of a bordered level of `size` takes its value: itself inside, and across the
// seam for the border (the octahedral map continues mirrored about each edge's midpoint).
std::pair<int, int> InteriorTexel(int i, int j, int size) {
  if (i < 0) {
    i = -1 - i;
    j = size - 1 - j;
  } else if (i >= size) {
    i = 2 * size - 1 - i;
    j = size - 1 - j;
  }
  if (j < 0) {
    j = -1 - j;
    i = size - 1 - i;
  } else if (j >= size) {
    j = 2 * size - 1 - j;
    i = size - 1 - i;
  }
  return {i, j};
}

// Copies the interior texels across the seams into the border.
void FillBorder(OctahedralLevel& level) {
  const int n = level.size;
  for (int j = -1; j <= n; ++j) {
    for (int i = -1; i <= n; ++i) {
      if (i >= 0 && i < n && j >= 0 && j < n) continue;
      const auto [si, sj] = InteriorTexel(i, j, n);
      for (int c = 0; c < 3; ++c)
        level.texels.c[c].MutableRow(size_t(j + 1))[i + 1] = level.texels.c[c].ConstRow(size_t(sj + 1))[si + 1];
    }
  }
}

OctahedralLevel MakeLevel(int size) { return {size, MakePlane3<float>(size_t(size) + 2, size_t(size) + 2, 0.0f)}; }

glm::vec3 Texel(const OctahedralLevel& level, int i, int j) {
  return {level.texels.c[0].ConstRow(size_t(j))[i], level.texels.c[1].ConstRow(size_t(j))[i],
          level.texels.c[2].ConstRow(size_t(j))[i]};
}

// Bilinear in the bordered level: texel i's centre at bordered coordinate i + 1.5.
glm::vec3 SampleLevel(const OctahedralLevel& level, const glm::vec2& uv) {
  const float n = float(level.size);
  const float x = uv.x * n + 0.5f, y = uv.y * n + 0.5f;
  const int i = std::min(int(x), level.size), j = std::min(int(y), level.size);
  const float fx = x - float(i), fy = y - float(j);
  const glm::vec3 top = Texel(level, i, j) * (1.0f - fx) + Texel(level, i + 1, j) * fx;
  const glm::vec3 bottom = Texel(level, i, j + 1) * (1.0f - fx) + Texel(level, i + 1, j + 1) * fx;
  return top * (1.0f - fy) + bottom * fy;
}

// The direction through the centre of texel (i, j) of a level of `size`, offset by (du, dv) texels.
glm::vec3 TexelDirection(int i, int j, int size, float du = 0.5f, float dv = 0.5f) {
  return OctahedralDecode({(float(i) + du) / float(size), (float(j) + dv) / float(size)});
}

// The solid angle of an element dA of the (u, v) square at `uv`, over dA: 4 / |p|^3 at the octahedron's
// point p = d / (|d.x| + |d.y| + |d.z|) of the direction d (the face's area over its projection
// onto the (u, v) square, times n.p / |p|^3), that is 4 (|d.x| + |d.y| + |d.z|)^3 for the unit d.
float SolidAngleDensity(const glm::vec2& uv) {
  const glm::vec3 d = OctahedralDecode(uv);
  const float l1 = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
  return 4.0f * l1 * l1 * l1;
}

// The real SH basis up to l = 2 at a unit direction.
std::array<float, 9> ShBasis(const glm::vec3& d) {
  return {0.282095f,
          0.488603f * d.y,
          0.488603f * d.z,
          0.488603f * d.x,
          1.092548f * d.x * d.y,
          1.092548f * d.y * d.z,
          0.315392f * (3.0f * d.z * d.z - 1.0f),
          1.092548f * d.x * d.z,
          0.546274f * (d.x * d.x - d.y * d.y)};
}

// 2x2 box down-sampling, for the prefilter's sources by footprint.
OctahedralLevel Downsample(const OctahedralLevel& source) {
  OctahedralLevel level = MakeLevel(std::max(source.size / 2, 1));
  for (int j = 0; j < level.size; ++j)
    for (int i = 0; i < level.size; ++i)
      for (int c = 0; c < 3; ++c) {
        const Plane<float>& s = source.texels.c[c];
        const int si = 2 * i + 1, sj = 2 * j + 1;
        const float sum = s.ConstRow(size_t(sj))[si] + s.ConstRow(size_t(sj))[si + 1] + s.ConstRow(size_t(sj) + 1)[si] +
                          s.ConstRow(size_t(sj) + 1)[si + 1];
        level.texels.c[c].MutableRow(size_t(j) + 1)[i + 1] = sum * 0.25f;
      }
  FillBorder(level);
  return level;
}

glm::vec2 Hammersley(uint32_t i, uint32_t n) {
  uint32_t bits = i;
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return {float(i) / float(n), float(bits) * 2.3283064365386963e-10f};
}

// The GGX-prefiltered radiance towards n with n = v = r (the split-sum's assumption), by
// filtered importance sampling (Krivanek & Colbert 2008): each sample reads the source mip whose
// texels cover the sample's share of solid angle, so few samples give no fireflies.
glm::vec3 Prefilter(const std::vector<OctahedralLevel>& mips, const glm::vec3& n, float roughness, int samples) {
  const float alpha = std::max(roughness * roughness, kMinGgxAlpha);
  const float a2 = alpha * alpha;
  const glm::vec3 up = std::abs(n.y) < 0.999f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
  const glm::vec3 t = glm::normalize(glm::cross(up, n));
  const glm::vec3 b = glm::cross(n, t);
  const float texelSolidAngle = 4.0f * kPi / float(mips[0].size * mips[0].size);
  glm::vec3 sum(0.0f);
  float weight = 0.0f;
  for (int s = 0; s < samples; ++s) {
    const glm::vec2 u = Hammersley(uint32_t(s), uint32_t(samples));
    const float phi = 2.0f * kPi * u.x;
    const float cosTheta = std::sqrt((1.0f - u.y) / (1.0f + (a2 - 1.0f) * u.y));
    const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    const glm::vec3 h = t * (sinTheta * std::cos(phi)) + b * (sinTheta * std::sin(phi)) + n * cosTheta;
    const float nDotH = cosTheta;
    const glm::vec3 l = h * (2.0f * nDotH) - n;
    const float nDotL = glm::dot(n, l);
    if (!(nDotL > 0.0f)) continue;
    // pdf(l) = D(h) n.h / (4 v.h) = D / 4 with v = n.
    const float pdf = GgxDistribution(nDotH, alpha) * 0.25f;
    const float sampleSolidAngle = 1.0f / (float(samples) * pdf);
    const float lod =
        std::clamp(0.5f * std::log2(sampleSolidAngle / texelSolidAngle) + 1.0f, 0.0f, float(mips.size() - 1));
    const int lower = int(lod);
    const int upper = std::min(lower + 1, int(mips.size()) - 1);
    const float f = lod - float(lower);
    const glm::vec2 uv = OctahedralEncode(glm::normalize(l));
    const glm::vec3 radiance =
        SampleLevel(mips[size_t(lower)], uv) * (1.0f - f) + SampleLevel(mips[size_t(upper)], uv) * f;
    sum += radiance * nDotL;
    weight += nDotL;
  }
  return weight > 0.0f ? sum / weight : SampleLevel(mips[0], OctahedralEncode(n));
}

}  // namespace

glm::vec2 OctahedralEncode(const glm::vec3& direction) {
  const float l1 = std::abs(direction.x) + std::abs(direction.y) + std::abs(direction.z);
  float x = direction.x / l1, z = direction.z / l1;
  if (direction.y < 0.0f) {
    const float fx = (1.0f - std::abs(z)) * SignNotZero(x);
    const float fz = (1.0f - std::abs(x)) * SignNotZero(z);
    x = fx;
    z = fz;
  }
  return {x * 0.5f + 0.5f, z * 0.5f + 0.5f};
}

glm::vec3 OctahedralDecode(const glm::vec2& uv) {
  float x = uv.x * 2.0f - 1.0f, z = uv.y * 2.0f - 1.0f;
  const float y = 1.0f - std::abs(x) - std::abs(z);
  if (y < 0.0f) {
    const float fx = (1.0f - std::abs(z)) * SignNotZero(x);
    const float fz = (1.0f - std::abs(x)) * SignNotZero(z);
    x = fx;
    z = fz;
  }
  return glm::normalize(glm::vec3(x, y, z));
}

EnvironmentLighting PrepareEnvironmentLighting(const Environment& environment,
                                               const EnvironmentLightingParams& params) {
  EnvironmentLighting lighting;
  lighting.source = environment;
  lighting.constant = environment.kind == EnvironmentKind::kConstant;
  lighting.constantRadiance = environment.radiance;
  if (lighting.constant) return lighting;
  SSGI_CHECK_GE(params.radianceSize, 2);
  // Level 0: the radiance, each texel the mean of 2x2 directions inside it.
  OctahedralLevel& radiance = lighting.levels[0];
  radiance = MakeLevel(params.radianceSize);
  ParallelForRowBands("environment.radiance", size_t(radiance.size), [&](size_t, size_t yBegin, size_t yEnd) {
    for (size_t j = yBegin; j < yEnd; ++j)
      for (int i = 0; i < radiance.size; ++i) {
        glm::vec3 sum(0.0f);
        for (float dv : {0.25f, 0.75f})
          for (float du : {0.25f, 0.75f}) sum += environment.Radiance(TexelDirection(i, int(j), radiance.size, du, dv));
        for (int c = 0; c < 3; ++c) radiance.texels.c[c].MutableRow(j + 1)[i + 1] = sum[c] * 0.25f;
      }
  });
  FillBorder(radiance);
  // The irradiance: level 0 projected on the SH basis with each texel's solid angle, in texel order.
  std::array<glm::vec3, 9> projected{};
  float solidAngle = 0.0f;
  for (int j = 0; j < radiance.size; ++j)
    for (int i = 0; i < radiance.size; ++i) {
      const glm::vec2 uv((float(i) + 0.5f) / float(radiance.size), (float(j) + 0.5f) / float(radiance.size));
      const float texelArea = 1.0f / float(radiance.size * radiance.size);
      const float omega = SolidAngleDensity(uv) * texelArea;
      const std::array<float, 9> y = ShBasis(OctahedralDecode(uv));
      const glm::vec3 value = Texel(radiance, i + 1, j + 1);
      for (int k = 0; k < 9; ++k) projected[size_t(k)] += value * (y[size_t(k)] * omega);
      solidAngle += omega;
    }
  // Normalised to the sphere's 4 pi (the texel-centre rule's small error), then convolved with the
  // clamped cosine: A_l / pi = 1, 2/3, 1/4 for l = 0, 1, 2.
  const float normalise = 4.0f * kPi / solidAngle;
  const float band[9] = {1.0f, 2.0f / 3.0f, 2.0f / 3.0f, 2.0f / 3.0f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f};
  for (int k = 0; k < 9; ++k) lighting.irradianceSh[size_t(k)] = projected[size_t(k)] * (normalise * band[k]);
  // The prefiltered levels, from level 0's mip chain.
  std::vector<OctahedralLevel> mips;
  mips.push_back({radiance.size, MakePlane3<float>(size_t(radiance.size) + 2, size_t(radiance.size) + 2, 0.0f)});
  for (int c = 0; c < 3; ++c)
    for (int j = 0; j < radiance.size + 2; ++j)
      std::copy_n(radiance.texels.c[c].ConstRow(size_t(j)), radiance.size + 2,
                  mips[0].texels.c[c].MutableRow(size_t(j)));
  while (mips.back().size > 1) mips.push_back(Downsample(mips.back()));
  for (int k = 1; k < kEnvironmentLevels; ++k) {
    OctahedralLevel& level = lighting.levels[size_t(k)];
    level = MakeLevel(std::max(params.prefilteredSize >> (k - 1), kMinLevelSize));
    const float roughness = float(k) / float(kEnvironmentLevels - 1);
    ParallelForRowBands("environment.prefilter", size_t(level.size), [&](size_t, size_t yBegin, size_t yEnd) {
      for (size_t j = yBegin; j < yEnd; ++j)
        for (int i = 0; i < level.size; ++i) {
          const glm::vec3 value =
              Prefilter(mips, TexelDirection(i, int(j), level.size), roughness, params.prefilterSamples);
          for (int c = 0; c < 3; ++c) level.texels.c[c].MutableRow(j + 1)[i + 1] = value[c];
        }
    });
    FillBorder(level);
  }
  return lighting;
}

bool SameEnvironment(const EnvironmentLighting& lighting, const Environment& environment) {
  return lighting.source.Same(environment);
}

glm::vec3 EnvironmentRadiance(const EnvironmentLighting& lighting, const glm::vec3& direction) {
  if (lighting.constant) return lighting.constantRadiance;
  return SampleLevel(lighting.levels[0], OctahedralEncode(direction));
}

glm::vec3 PrefilteredEnvironment(const EnvironmentLighting& lighting, const glm::vec3& direction, float roughness) {
  if (lighting.constant) return lighting.constantRadiance;
  const float position = std::clamp(roughness, 0.0f, 1.0f) * float(kEnvironmentLevels - 1);
  const int lower = std::min(int(position), kEnvironmentLevels - 2);
  const float f = position - float(lower);
  const glm::vec2 uv = OctahedralEncode(direction);
  return SampleLevel(lighting.levels[size_t(lower)], uv) * (1.0f - f) +
         SampleLevel(lighting.levels[size_t(lower) + 1], uv) * f;
}

glm::vec3 EnvironmentIrradiance(const EnvironmentLighting& lighting, const glm::vec3& n) {
  if (lighting.constant) return lighting.constantRadiance;
  // In this order, each product left to right (the twins follow it).
  const std::array<float, 9> y = ShBasis(n);
  glm::vec3 sum = lighting.irradianceSh[0] * y[0];
  for (int k = 1; k < 9; ++k) sum = sum + lighting.irradianceSh[size_t(k)] * y[size_t(k)];
  return {std::max(sum.x, 0.0f), std::max(sum.y, 0.0f), std::max(sum.z, 0.0f)};
}

}  // namespace ssgi
