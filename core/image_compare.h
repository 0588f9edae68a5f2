// Image comparison for accuracy measurements (docs/design.md §10): error metrics between a test image
// and a reference, on linear HDR values, plus a perceptual score.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace ssgi {

// A float image with named channels, interleaved, top row first.
struct FloatImage {
  int width = 0, height = 0;
  std::vector<std::string> channelNames;
  std::vector<float> pixels;  // width * height * channelNames.size()
  // The file stores integer codes (PNG, JPEG, 8- or 16-bit TIFF): display-encoded values such as 8-bit
  // sRGB, read here as code / max, not linear radiance.
  bool integerCodes = false;
  size_t Channels() const { return channelNames.size(); }
};

// Reads an image file (any format OpenImageIO reads) as float. Throws InputError naming the file.
FloatImage ReadFloatImage(const std::filesystem::path& file);

// The channels of `layer` in `image`: "LAYER.R", "LAYER.G", "LAYER.B" when present, else the single
// channel "LAYER"; an empty layer means R, G, B (or the first three channels). Throws InputError
// naming `file` and the channels it has when the layer is missing.
FloatImage SelectLayer(const FloatImage& image, const std::string& layer, const std::filesystem::path& file);
// The same channels, or nullopt when the layer is missing (an optional per-pass buffer).
std::optional<FloatImage> FindLayer(const FloatImage& image, const std::string& layer);

// `image` resampled to width x height with a triangle (bilinear) filter, pixel centres aligned:
// how a frame rendered below the reference's resolution is brought to it for comparison.
FloatImage ResizeImage(const FloatImage& image, int width, int height);

// `image` averaged over blocks of factor x factor pixels (its size a multiple of factor): a render at
// `factor` times the size, one sample at each sub-pixel's centre, becomes a box filter of each pixel
// sampled on a regular factor x factor grid.
FloatImage BoxDownsampled(const FloatImage& image, int factor);

struct ImageDifference {
  double rmse = 0.0;           // sqrt(mean over pixels and channels of (a - b)^2)
  double peak = 0.0;           // max of b over pixels and channels (>= 1e-12)
  double psnr = 0.0;           // 10 log10(peak^2 / mse); +inf when equal
  double maxError = 0.0;       // max over pixels and channels of |a - b|
  int maxX = 0, maxY = 0;      // where it is (first in row-major order)
  // RMSE of x / (1 + x) per channel: bounded, so a few extreme HDR values (a reflected sun) cannot
  // drown every other difference; the error the eye sees, roughly.
  double rmseDisplay = 0.0;
  double ssim = 1.0;           // mean SSIM (Wang et al. 2004) of the tonemapped luminance, 1 = identical
  size_t nonFinite = 0;        // samples of a or b that are NaN or infinite (excluded from the metrics)
};

// Compares `a` (test) with `b` (reference): same size and channel count required (checked by the
// caller). SSIM uses an 11x11 Gaussian window (sigma 1.5) with C1 = (0.01)^2, C2 = (0.03)^2 on
// luminance (Rec. 709 weights of the first three channels, or the single channel) after
// x / (1 + x) tonemapping, so HDR values compare on a bounded, perceptually ordered scale.
ImageDifference CompareImages(const FloatImage& a, const FloatImage& b);

// Where in the image an error is: the screen-space pipeline's error differs in kind between lit
// pixels, pixels in the shadowed light's shadow, reflective pixels and the background.
enum ImageRegion : uint8_t {
  kRegionLit = 1,         // the shadowed light's filtered visibility >= 0.5 (every covered pixel without shadows)
  kRegionInShadow = 2,    // its visibility < 0.5
  kRegionReflective = 4,  // roughness below the trace's cut-off (also lit or in shadow)
  kRegionBackground = 8,  // no geometry (depth +inf)
};
inline constexpr ImageRegion kImageRegions[] = {kRegionLit, kRegionInShadow, kRegionReflective, kRegionBackground};
// "lit", "in shadow", "reflective", "background".
const char* ImageRegionName(ImageRegion region);

// Per pixel, the regions (ImageRegion bits) it belongs to, from the layers of a frame's dump:
// "depth", "roughness" and, where the frame ran shadows, "shadow.visibility". Throws InputError
// naming `file` when depth or roughness is missing.
std::vector<uint8_t> ClassifyRegions(const FloatImage& dump, float roughnessCutoff, const std::filesystem::path& file);

struct RegionDifference {
  ImageRegion region;
  size_t pixels = 0;
  double rmse = 0.0;         // over the region's pixels and every channel
  double rmseDisplay = 0.0;  // the same of x / (1 + x)
  // Mean of a over mean of b, of the Rec. 709 luminance (or the single channel): above 1 the test
  // is too bright there, below 1 too dark; NaN where b's mean is 0.
  double meanRatio = 0.0;
};
// `a` (test) against `b` (reference) in each region of `regions` (ClassifyRegions, same size).
std::vector<RegionDifference> CompareRegions(const FloatImage& a, const FloatImage& b,
                                             const std::vector<uint8_t>& regions);

// The heat maps' colour of t in [0, 1] (clamped): black (0) through red and yellow to white (1), in
// three equal thirds; 8-bit RGB into rgb[0..2].
void HeatmapColour(double t, uint8_t* rgb);

// Per-pixel error |a - b| (Euclidean over channels) as an 8-bit RGB heat map, black (0) through red
// and yellow to white (>= scale), with a legend below it: the colour scale from 0 to `scale`, labelled.
// scale <= 0 picks the 99th percentile of the per-pixel errors (or their maximum where that is 0), so
// a few outliers do not turn the rest of the map black.
struct Heatmap {
  int width = 0, height = 0;  // the map's and the legend's rows: height = the image's + kHeatmapLegendRows
  std::vector<uint8_t> rgb;
  double scale = 0.0;          // the error shown white
  double shareAboveScale = 0.0;  // of the pixels, whose error is above the scale
};
inline constexpr int kHeatmapLegendRows = 24;
Heatmap ErrorHeatmap(const FloatImage& a, const FloatImage& b, double scale);

}  // namespace ssgi
