#include "core/environment.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/brdf.h"
#include "core/check.h"
#include "core/error.h"
#include "core/image_compare.h"

namespace ssgi {
namespace {

constexpr int kSkyMapWidth = 1024, kSkyMapHeight = 512;

float Luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// The first index i with cdf[i + 1] > u, for a CDF of n + 1 entries from 0 to 1.
size_t FindInterval(const std::vector<float>& cdf, size_t offset, size_t n, float u) {
  const auto begin = cdf.begin() + std::ptrdiff_t(offset);
  const auto it = std::upper_bound(begin + 1, begin + std::ptrdiff_t(n) + 1, u);
  return std::min(size_t(it - begin) - 1, n - 1);
}

uint64_t Fnv(uint64_t hash, const void* data, size_t bytes) {
  const auto* p = static_cast<const uint8_t*>(data);
  for (size_t i = 0; i < bytes; ++i) hash = (hash ^ p[i]) * 1099511628211ull;
  return hash;
}

}  // namespace

glm::vec3 SkyRadiance(const SkyParams& sky, const glm::vec3& d) {
  glm::vec3 colour;
  if (d.y >= 0.0f) {
    const float t = 1.0f - d.y;
    colour = sky.zenith + (sky.horizon - sky.zenith) * (t * t * t);
  } else {
    const float t = 1.0f + d.y;
    const float t2 = t * t, t4 = t2 * t2;
    colour = sky.ground + (sky.horizon - sky.ground) * (t4 * t4);
  }
  const float facing = std::max(0.0f, glm::dot(d, sky.sunDirection));
  const float f2 = facing * facing, f4 = f2 * f2, f8 = f4 * f4;
  return colour + sky.sunGlow * (f8 * f8);
}

EnvironmentMap::EnvironmentMap(int width, int height, std::vector<glm::vec3> texels, float rotationTurns)
    : width_(width),
      height_(height),
      rotationTurns_(rotationTurns - std::floor(rotationTurns)),
      texels_(std::move(texels)) {
  SSGI_CHECK(width_ > 0 && height_ > 0);
  SSGI_CHECK_EQ(texels_.size(), size_t(width_) * size_t(height_));
  conditionalCdf_.assign(size_t(height_) * size_t(width_ + 1), 0.0f);
  marginalCdf_.assign(size_t(height_) + 1, 0.0f);
  rowWeights_.assign(size_t(height_), 0.0);
  glm::dvec3 weightedSum(0.0);
  double solidAngleSum = 0.0;
  for (int j = 0; j < height_; ++j) {
    const double sinTheta = std::sin(kPi * (double(j) + 0.5) / double(height_));
    double row = 0.0;
    float* cdf = &conditionalCdf_[size_t(j) * size_t(width_ + 1)];
    for (int i = 0; i < width_; ++i) {
      const glm::vec3& t = texels_[size_t(j) * size_t(width_) + size_t(i)];
      row += double(std::max(Luminance(t), 0.0f)) * sinTheta;
      cdf[i + 1] = float(row);
      weightedSum += glm::dvec3(t) * sinTheta;
      solidAngleSum += sinTheta;
    }
    for (int i = 1; i <= width_; ++i) cdf[i] = row > 0.0 ? float(double(cdf[i]) / row) : float(i) / float(width_);
    cdf[width_] = 1.0f;
    rowWeights_[size_t(j)] = row;
    integral_ += row;
    marginalCdf_[size_t(j) + 1] = float(integral_);
  }
  for (int j = 1; j <= height_; ++j)
    marginalCdf_[size_t(j)] =
        integral_ > 0.0 ? float(double(marginalCdf_[size_t(j)]) / integral_) : float(j) / float(height_);
  marginalCdf_[size_t(height_)] = 1.0f;
  mean_ = glm::vec3(weightedSum / std::max(solidAngleSum, 1e-30));
  hash_ = Fnv(1469598103934665603ull, texels_.data(), texels_.size() * sizeof(glm::vec3));
  hash_ = Fnv(hash_, &width_, sizeof(width_));
  hash_ = Fnv(hash_, &rotationTurns_, sizeof(rotationTurns_));
}

size_t EnvironmentMap::TexelOf(const glm::vec3& d) const {
  float u = 0.5f + std::atan2(d.x, -d.z) / (2.0f * kPi) + rotationTurns_;
  u -= std::floor(u);
  const float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kPi;
  const int i = std::min(int(u * float(width_)), width_ - 1);
  const int j = std::min(int(v * float(height_)), height_ - 1);
  return size_t(j) * size_t(width_) + size_t(std::max(i, 0));
}

glm::vec3 EnvironmentMap::Radiance(const glm::vec3& direction) const { return texels_[TexelOf(direction)]; }

EnvironmentSample EnvironmentMap::Sample(float u1, float u2) const {
  // A row by the marginal CDF, a column by its conditional CDF, then uniformly within the texel's
  // (u, v) rectangle.
  const size_t j = FindInterval(marginalCdf_, 0, size_t(height_), u1);
  const float rowStart = marginalCdf_[j], rowWidth = marginalCdf_[j + 1] - rowStart;
  const float du1 = rowWidth > 0.0f ? std::clamp((u1 - rowStart) / rowWidth, 0.0f, 0.99999994f) : 0.5f;
  const size_t offset = j * size_t(width_ + 1);
  const size_t i = FindInterval(conditionalCdf_, offset, size_t(width_), u2);
  const float columnStart = conditionalCdf_[offset + i], columnWidth = conditionalCdf_[offset + i + 1] - columnStart;
  const float du2 = columnWidth > 0.0f ? std::clamp((u2 - columnStart) / columnWidth, 0.0f, 0.99999994f) : 0.5f;
  const float u = (float(i) + du2) / float(width_), v = (float(j) + du1) / float(height_);
  const float theta = v * kPi, phi = (u - 0.5f - rotationTurns_) * 2.0f * kPi;
  const glm::vec3 direction(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi));
  return {direction, Radiance(direction), Pdf(direction)};
}

float EnvironmentMap::Pdf(const glm::vec3& direction) const {
  if (!(integral_ > 0.0)) return 1.0f / (4.0f * kPi);
  const size_t texel = TexelOf(direction);
  const size_t j = texel / size_t(width_), i = texel % size_t(width_);
  const float sinTheta = float(std::sin(kPi * (double(j) + 0.5) / double(height_)));
  if (!(sinTheta > 0.0f)) return 0.0f;
  const size_t offset = j * size_t(width_ + 1);
  // The texel's probability over its solid angle, (2 pi / width)(pi / height) sin(theta).
  const double probability = double(conditionalCdf_[offset + i + 1] - conditionalCdf_[offset + i]) *
                             double(marginalCdf_[j + 1] - marginalCdf_[j]);
  const double solidAngle = (2.0 * kPi / double(width_)) * (kPi / double(height_)) * double(sinTheta);
  return float(probability / solidAngle);
}

EnvironmentSample Environment::Sample(float u1, float u2) const {
  if (map) return map->Sample(u1, u2);
  const float z = 1.0f - 2.0f * u1;
  const float r = std::sqrt(std::fmax(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * u2;
  const glm::vec3 direction(r * std::cos(phi), r * std::sin(phi), z);
  return {direction, Radiance(direction), Pdf(direction)};
}

float Environment::Pdf(const glm::vec3& direction) const { return map ? map->Pdf(direction) : 1.0f / (4.0f * kPi); }

bool Environment::Same(const Environment& other) const {
  if (kind != other.kind) return false;
  if (kind == EnvironmentKind::kConstant) return radiance == other.radiance;
  return map && other.map && map->Hash() == other.map->Hash();
}

Environment MakeSkyEnvironment(const SkyParams& sky) {
  std::vector<glm::vec3> texels(size_t(kSkyMapWidth) * size_t(kSkyMapHeight));
  for (int j = 0; j < kSkyMapHeight; ++j) {
    const float theta = kPi * (float(j) + 0.5f) / float(kSkyMapHeight);
    for (int i = 0; i < kSkyMapWidth; ++i) {
      const float phi = (float(i) + 0.5f) / float(kSkyMapWidth) * 2.0f * kPi - kPi;
      const glm::vec3 d(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi));
      texels[size_t(j) * size_t(kSkyMapWidth) + size_t(i)] = SkyRadiance(sky, d);
    }
  }
  Environment environment;
  environment.kind = EnvironmentKind::kSky;
  environment.sky = sky;
  environment.map = std::make_shared<EnvironmentMap>(kSkyMapWidth, kSkyMapHeight, std::move(texels), 0.0f);
  return environment;
}

Environment LoadImageEnvironment(const std::filesystem::path& file, float rotationDegrees, float intensity) {
  const FloatImage image = ReadFloatImage(file);
  if (image.Channels() < 3) throw InputError(file, "an environment image needs three channels (RGB)");
  if (image.width < 2 || image.height < 1) throw InputError(file, "an environment image must be at least 2x1");
  std::vector<glm::vec3> texels(size_t(image.width) * size_t(image.height));
  const size_t channels = image.Channels();
  for (size_t p = 0; p < texels.size(); ++p) {
    for (int c = 0; c < 3; ++c) {
      const float value = image.pixels[p * channels + size_t(c)];
      if (!std::isfinite(value) || value < 0.0f)
        throw InputError(file, "pixel (" + std::to_string(p % size_t(image.width)) + ", " +
                                   std::to_string(p / size_t(image.width)) + ") is " +
                                   (std::isnan(value)       ? "NaN"
                                    : !std::isfinite(value) ? "infinite"
                                                            : "negative"));
      texels[p][c] = value * intensity;
    }
  }
  Environment environment;
  environment.kind = EnvironmentKind::kImage;
  environment.file = file;
  environment.rotationDegrees = rotationDegrees;
  environment.intensity = intensity;
  environment.map =
      std::make_shared<EnvironmentMap>(image.width, image.height, std::move(texels), rotationDegrees / 360.0f);
  return environment;
}

}  // namespace ssgi
