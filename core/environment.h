// The environment: light from infinitely far away, arriving from every direction no geometry
// blocks. It is what the camera sees where no geometry covers a pixel, and it lights every surface,
// as a world colour does in every physically based renderer (docs/design.md §2). A scene file's
// "environment" (docs/user-guide.md "Scene files"): a constant radiance, an analytic sky (zenith,
// horizon and ground colours and a glow around the sun), or an HDR image (equirectangular, as users
// bring them, with a rotation about the up axis and an intensity).
//
// It is a light like any other to the Embree reference's path tracer, which samples it (Sample,
// Pdf) and weights those samples against BSDF sampling with multiple importance sampling (Veach
// 1997, "Robust Monte Carlo Methods for Light Transport Simulation", chapter 9). A sky or an image
// is held as an equirectangular map of its radiance, piecewise constant over the map's texels, and
// sampled in proportion to each texel's luminance times its solid angle, as pbrt-v4's
// ImageInfiniteLight does (Pharr et al., "Physically Based Rendering", 4th ed., §12.5.2); Pdf is
// the density Sample draws from. The screen-space passes read it through the tables of
// core/environment_lighting.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/glm.hpp>
#include <memory>
#include <vector>

namespace ssgi {

enum class EnvironmentKind {
  kConstant,  // the same radiance from every direction
  kSky,       // the analytic sky of SkyParams
  kImage,     // an equirectangular HDR image
};

// The analytic sky: above the horizon the colour runs from `horizon` (elevation 0) to `zenith` as
// zenith + (horizon - zenith) (1 - y)^3 with y the direction's up component; below it from `horizon`
// to `ground` as ground + (horizon - ground) (1 + y)^8, a short band of haze; plus a glow around the
// sun, sunGlow max(0, d . sun)^16.
struct SkyParams {
  glm::vec3 zenith{0.15f, 0.3f, 0.65f};
  glm::vec3 horizon{0.7f, 0.75f, 0.8f};
  glm::vec3 ground{0.2f, 0.18f, 0.16f};
  glm::vec3 sunGlow{0.0f};
  glm::vec3 sunDirection{0.0f, 1.0f, 0.0f};  // unit, towards the sun
};
glm::vec3 SkyRadiance(const SkyParams& sky, const glm::vec3& direction);

// A direction drawn from an environment's sampling density.
struct EnvironmentSample {
  glm::vec3 direction;  // unit, world space: light arrives along -direction
  glm::vec3 radiance;   // Radiance(direction)
  float pdf;            // solid-angle density of `direction` (1/sr), > 0; Pdf(direction)
};

// A radiance over the sphere as an equirectangular map, y up: a direction (x, y, z) is at
// u = 0.5 + atan2(x, -z) / (2 pi) + rotation (wrapped to [0, 1)), v = acos(y) / pi; texel (i, j)
// covers [i, i + 1) / width x [j, j + 1) / height, row 0 at the zenith. The radiance is the texel's
// (piecewise constant), which is what the sampling distribution is made of.
class EnvironmentMap {
 public:
  // `texels` row by row; `rotationTurns` turns the map about +y (a fraction of a turn, wrapped).
  EnvironmentMap(int width, int height, std::vector<glm::vec3> texels, float rotationTurns);
  int width() const { return width_; }
  int height() const { return height_; }
  glm::vec3 Radiance(const glm::vec3& direction) const;
  EnvironmentSample Sample(float u1, float u2) const;
  float Pdf(const glm::vec3& direction) const;
  bool IsBlack() const { return !(integral_ > 0.0); }
  // The mean radiance over the sphere (solid-angle weighted).
  glm::vec3 MeanRadiance() const { return mean_; }
  // The texels' bits, the size and the rotation: equal hashes, the same environment.
  uint64_t Hash() const { return hash_; }

 private:
  // The texel a direction falls in.
  size_t TexelOf(const glm::vec3& direction) const;
  int width_, height_;
  float rotationTurns_;
  std::vector<glm::vec3> texels_;
  // The sampling distribution: per row its conditional CDF over columns (width + 1 entries), and
  // the marginal CDF over rows (height + 1), of luminance times sin(theta) (the texel's solid angle).
  std::vector<float> conditionalCdf_, marginalCdf_;
  std::vector<double> rowWeights_;
  double integral_ = 0.0;  // sum over texels of the sampling weights
  glm::vec3 mean_{0.0f};
  uint64_t hash_ = 0;
};

struct Environment {
  EnvironmentKind kind = EnvironmentKind::kConstant;
  glm::vec3 radiance{0.0f};  // kConstant: linear RGB radiance, W/(m^2 sr), each component >= 0
  SkyParams sky = {};        // kSky
  std::filesystem::path file = {};                 // kImage: the image, as found when the scene was loaded
  float rotationDegrees = 0.0f;                    // kImage: about +y
  float intensity = 1.0f;                          // kImage: scales the image
  std::shared_ptr<const EnvironmentMap> map = {};  // kSky, kImage

  // The radiance arriving along -direction, that is seen looking along `direction` (world space,
  // unit length).
  glm::vec3 Radiance(const glm::vec3& direction) const { return map ? map->Radiance(direction) : radiance; }
  bool IsBlack() const { return map ? map->IsBlack() : radiance == glm::vec3(0.0f); }
  // The mean radiance over the sphere: what a frame without the sky light shows where no geometry is.
  glm::vec3 MeanRadiance() const { return map ? map->MeanRadiance() : radiance; }

  // A direction from two uniforms in [0, 1), drawn with a density close to the radiance's
  // distribution over the sphere. kConstant: uniform over the sphere (pbrt-v4 §A.5.2,
  // SampleUniformSphere), density 1 / (4 pi): every direction carries the same radiance.
  EnvironmentSample Sample(float u1, float u2) const;
  // The density Sample draws `direction` (unit) with.
  float Pdf(const glm::vec3& direction) const;

  // Whether two environments give the same radiance everywhere (a frame keeps its tables while
  // its environment is the same).
  bool Same(const Environment& other) const;
};

// A constant environment of that radiance.
inline Environment ConstantEnvironment(const glm::vec3& radiance) {
  Environment environment;
  environment.radiance = radiance;
  return environment;
}
// An analytic sky, its radiance held in a 1024 x 512 map.
Environment MakeSkyEnvironment(const SkyParams& sky);
// An HDR image (.exr, .hdr, or any format OpenImageIO reads) as an environment, its RGB channels
// times `intensity`. Throws InputError naming the file when it cannot be read, has fewer than three
// channels, or holds a negative, NaN or infinite value.
Environment LoadImageEnvironment(const std::filesystem::path& file, float rotationDegrees, float intensity);

}  // namespace ssgi
