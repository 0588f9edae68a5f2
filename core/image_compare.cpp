#include "core/image_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include "core/check.h"
#include "core/error.h"

namespace ssgi {
namespace {

constexpr int kSsimRadius = 5;  // 11x11 window
constexpr double kSsimSigma = 1.5;
constexpr double kSsimC1 = 0.01 * 0.01;
constexpr double kSsimC2 = 0.03 * 0.03;

bool Finite(float v) { return std::isfinite(v); }

// Rec. 709 luminance of one pixel's first three channels (or its single channel); non-finite
// samples count as 0.
double Luminance(const float* p, size_t channels) {
  if (channels < 3) return Finite(p[0]) ? p[0] : 0.0;
  return 0.2126 * (Finite(p[0]) ? p[0] : 0.0) + 0.7152 * (Finite(p[1]) ? p[1] : 0.0) +
         0.0722 * (Finite(p[2]) ? p[2] : 0.0);
}

// Tonemapped luminance in [0, 1) per pixel.
std::vector<double> TonemappedLuminance(const FloatImage& image) {
  const size_t n = size_t(image.width) * size_t(image.height);
  const size_t channels = image.Channels();
  std::vector<double> out(n);
  for (size_t i = 0; i < n; ++i) {
    const double y = std::max(Luminance(&image.pixels[i * channels], channels), 0.0);
    out[i] = y / (1.0 + y);
  }
  return out;
}

// Separable Gaussian blur with clamp-to-edge addressing, fixed summation order.
std::vector<double> Blur(const std::vector<double>& in, int width, int height, const std::vector<double>& kernel) {
  std::vector<double> tmp(in.size()), out(in.size());
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double sum = 0.0;
      for (int k = -kSsimRadius; k <= kSsimRadius; ++k)
        sum += kernel[k + kSsimRadius] * in[size_t(y) * width + std::clamp(x + k, 0, width - 1)];
      tmp[size_t(y) * width + x] = sum;
    }
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double sum = 0.0;
      for (int k = -kSsimRadius; k <= kSsimRadius; ++k)
        sum += kernel[k + kSsimRadius] * tmp[size_t(std::clamp(y + k, 0, height - 1)) * width + x];
      out[size_t(y) * width + x] = sum;
    }
  return out;
}

double MeanSsim(const FloatImage& a, const FloatImage& b) {
  std::vector<double> kernel(2 * kSsimRadius + 1);
  double total = 0.0;
  for (int k = -kSsimRadius; k <= kSsimRadius; ++k) total += kernel[k + kSsimRadius] = std::exp(-k * k / (2 * kSsimSigma * kSsimSigma));
  for (double& w : kernel) w /= total;
  const std::vector<double> la = TonemappedLuminance(a), lb = TonemappedLuminance(b);
  std::vector<double> aa(la.size()), bb(la.size()), ab(la.size());
  for (size_t i = 0; i < la.size(); ++i) {
    aa[i] = la[i] * la[i];
    bb[i] = lb[i] * lb[i];
    ab[i] = la[i] * lb[i];
  }
  const std::vector<double> muA = Blur(la, a.width, a.height, kernel), muB = Blur(lb, a.width, a.height, kernel);
  const std::vector<double> sAA = Blur(aa, a.width, a.height, kernel), sBB = Blur(bb, a.width, a.height, kernel);
  const std::vector<double> sAB = Blur(ab, a.width, a.height, kernel);
  double sum = 0.0;
  for (size_t i = 0; i < la.size(); ++i) {
    const double varA = sAA[i] - muA[i] * muA[i], varB = sBB[i] - muB[i] * muB[i];
    const double cov = sAB[i] - muA[i] * muB[i];
    sum += ((2 * muA[i] * muB[i] + kSsimC1) * (2 * cov + kSsimC2)) /
           ((muA[i] * muA[i] + muB[i] * muB[i] + kSsimC1) * (varA + varB + kSsimC2));
  }
  return sum / double(la.size());
}

}  // namespace

const char* ImageRegionName(ImageRegion region) {
  switch (region) {
    case kRegionLit:
      return "lit";
    case kRegionInShadow:
      return "in shadow";
    case kRegionReflective:
      return "reflective";
    case kRegionBackground:
      return "background";
  }
  return "";
}

std::vector<uint8_t> ClassifyRegions(const FloatImage& dump, float roughnessCutoff, const std::filesystem::path& file) {
  const auto channel = [&](const std::string& name) -> std::optional<FloatImage> { return FindLayer(dump, name); };
  const std::optional<FloatImage> depth = channel("depth"), roughness = channel("roughness");
  if (!depth || !roughness || depth->Channels() != 1 || roughness->Channels() != 1)
    throw InputError(file, "has no 'depth' and 'roughness' layers to tell the regions by: give a --dump of the frame");
  const std::optional<FloatImage> visibility = channel("shadow.visibility");
  const size_t n = size_t(dump.width) * size_t(dump.height);
  std::vector<uint8_t> regions(n, 0);
  for (size_t i = 0; i < n; ++i) {
    if (!(depth->pixels[i] < std::numeric_limits<float>::infinity())) {
      regions[i] = kRegionBackground;
      continue;
    }
    const bool lit = !visibility || visibility->pixels[i] >= 0.5f;
    regions[i] = uint8_t((lit ? kRegionLit : kRegionInShadow) |
                         (roughness->pixels[i] < roughnessCutoff ? kRegionReflective : 0));
  }
  return regions;
}

std::vector<RegionDifference> CompareRegions(const FloatImage& a, const FloatImage& b,
                                             const std::vector<uint8_t>& regions) {
  SSGI_CHECK(a.width == b.width && a.height == b.height && a.Channels() == b.Channels());
  const size_t n = size_t(a.width) * size_t(a.height), channels = a.Channels();
  SSGI_CHECK_EQ(regions.size(), n);
  std::vector<RegionDifference> out;
  for (ImageRegion region : kImageRegions) {
    RegionDifference d{region};
    double squared = 0.0, squaredDisplay = 0.0, sumA = 0.0, sumB = 0.0;
    size_t samples = 0;
    for (size_t i = 0; i < n; ++i) {
      if (!(regions[i] & region)) continue;
      const float* pa = &a.pixels[i * channels];
      const float* pb = &b.pixels[i * channels];
      bool finite = true;
      for (size_t c = 0; c < channels; ++c) finite = finite && Finite(pa[c]) && Finite(pb[c]);
      if (!finite) continue;
      ++d.pixels;
      for (size_t c = 0; c < channels; ++c) {
        const double e = double(pa[c]) - double(pb[c]);
        const double ta = std::max(double(pa[c]), 0.0), tb = std::max(double(pb[c]), 0.0);
        const double ed = ta / (1.0 + ta) - tb / (1.0 + tb);
        squared += e * e;
        squaredDisplay += ed * ed;
        ++samples;
      }
      sumA += Luminance(pa, channels);
      sumB += Luminance(pb, channels);
    }
    d.rmse = samples > 0 ? std::sqrt(squared / double(samples)) : 0.0;
    d.rmseDisplay = samples > 0 ? std::sqrt(squaredDisplay / double(samples)) : 0.0;
    d.meanRatio = sumB > 0.0 ? sumA / sumB : std::numeric_limits<double>::quiet_NaN();
    out.push_back(d);
  }
  return out;
}

FloatImage BoxDownsampled(const FloatImage& image, int factor) {
  SSGI_CHECK(factor > 0 && image.width % factor == 0 && image.height % factor == 0);
  FloatImage out{image.width / factor, image.height / factor, image.channelNames, {}, image.integerCodes};
  const size_t channels = image.Channels();
  std::vector<double> sums(size_t(out.width) * size_t(out.height) * channels, 0.0);
  for (size_t y = 0; y < size_t(image.height); ++y)
    for (size_t x = 0; x < size_t(image.width); ++x)
      for (size_t c = 0; c < channels; ++c)
        sums[((y / size_t(factor)) * size_t(out.width) + x / size_t(factor)) * channels + c] +=
            image.pixels[(y * size_t(image.width) + x) * channels + c];
  out.pixels.resize(sums.size());
  const double area = double(factor) * double(factor);
  for (size_t i = 0; i < sums.size(); ++i) out.pixels[i] = float(sums[i] / area);
  return out;
}

FloatImage ResizeImage(const FloatImage& image, int width, int height) {
  SSGI_CHECK(width > 0 && height > 0);
  const int channels = int(image.Channels());
  // The source buffer wraps image.pixels read-only; OIIO's ImageBuf takes a non-const pointer.
  OIIO::ImageBuf source(OIIO::ImageSpec(image.width, image.height, channels, OIIO::TypeDesc::FLOAT),
                        const_cast<float*>(image.pixels.data()));
  const OIIO::ImageBuf resized =
      OIIO::ImageBufAlgo::resize(source, "triangle", 0.0f, OIIO::ROI(0, width, 0, height, 0, 1, 0, channels), 1);
  SSGI_CHECK(!resized.has_error());
  FloatImage out;
  out.width = width;
  out.height = height;
  out.channelNames = image.channelNames;
  out.pixels.resize(size_t(width) * size_t(height) * size_t(channels));
  SSGI_CHECK(resized.get_pixels(OIIO::ROI(0, width, 0, height, 0, 1, 0, channels), OIIO::TypeDesc::FLOAT,
                                out.pixels.data()));
  return out;
}

FloatImage ReadFloatImage(const std::filesystem::path& file) {
  auto in = OIIO::ImageInput::open(file.string());
  if (!in) throw InputError(file, "cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  FloatImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.channelNames = spec.channelnames;
  image.integerCodes = !spec.format.is_floating_point();
  image.pixels.resize(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data()))
    throw InputError(file, "cannot read image: " + in->geterror());
  return image;
}

std::optional<FloatImage> FindLayer(const FloatImage& image, const std::string& layer) {
  auto find = [&](const std::string& name) {
    const auto it = std::find(image.channelNames.begin(), image.channelNames.end(), name);
    return it == image.channelNames.end() ? -1 : int(it - image.channelNames.begin());
  };
  std::vector<int> picked;
  const std::string prefix = layer.empty() ? "" : layer + ".";
  for (const char* c : {"R", "G", "B"})
    if (find(prefix + c) >= 0) picked.push_back(find(prefix + c));
  if (picked.size() != 3) {
    picked.clear();
    if (!layer.empty() && find(layer) >= 0) {
      picked.push_back(find(layer));
    } else if (layer.empty() && image.Channels() >= 3) {
      picked = {0, 1, 2};
    } else {
      return std::nullopt;
    }
  }
  FloatImage out;
  out.width = image.width;
  out.height = image.height;
  for (int c : picked) out.channelNames.push_back(image.channelNames[c]);
  const size_t n = size_t(image.width) * size_t(image.height);
  out.pixels.resize(n * picked.size());
  for (size_t i = 0; i < n; ++i)
    for (size_t c = 0; c < picked.size(); ++c) out.pixels[i * picked.size() + c] = image.pixels[i * image.Channels() + picked[c]];
  return out;
}

FloatImage SelectLayer(const FloatImage& image, const std::string& layer, const std::filesystem::path& file) {
  std::optional<FloatImage> picked = FindLayer(image, layer);
  if (!picked) {
    std::string names;
    for (const std::string& n : image.channelNames) names += (names.empty() ? "" : ", ") + n;
    throw InputError(file, "no channels for layer '" + layer + "' (the image has: " + names + ")");
  }
  return std::move(*picked);
}

ImageDifference CompareImages(const FloatImage& a, const FloatImage& b) {
  SSGI_CHECK_EQ(a.width, b.width);
  SSGI_CHECK_EQ(a.height, b.height);
  SSGI_CHECK_EQ(a.Channels(), b.Channels());
  ImageDifference d;
  double sumSquares = 0.0, sumDisplaySquares = 0.0, peak = 0.0;
  size_t counted = 0;
  const size_t channels = a.Channels();
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const float va = a.pixels[i], vb = b.pixels[i];
    if (!Finite(va) || !Finite(vb)) {
      ++d.nonFinite;
      continue;
    }
    const double e = double(va) - double(vb);
    sumSquares += e * e;
    const double da = std::max(double(va), 0.0), db = std::max(double(vb), 0.0);
    const double displayError = da / (1.0 + da) - db / (1.0 + db);
    sumDisplaySquares += displayError * displayError;
    ++counted;
    peak = std::max(peak, double(vb));
    if (std::abs(e) > d.maxError) {
      d.maxError = std::abs(e);
      d.maxX = int((i / channels) % size_t(a.width));
      d.maxY = int((i / channels) / size_t(a.width));
    }
  }
  const double mse = counted > 0 ? sumSquares / double(counted) : 0.0;
  d.rmse = std::sqrt(mse);
  d.rmseDisplay = counted > 0 ? std::sqrt(sumDisplaySquares / double(counted)) : 0.0;
  d.peak = peak = std::max(peak, 1e-12);
  d.psnr = mse > 0.0 ? 10.0 * std::log10(peak * peak / mse) : std::numeric_limits<double>::infinity();
  d.ssim = MeanSsim(a, b);
  return d;
}

namespace {

// A 3x5 pixel font for the legend's numbers: each glyph five rows of three bits, the top row first.
constexpr struct {
  char c;
  uint8_t rows[5];
} kGlyphs[] = {{'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}}, {'3', {7, 1, 7, 1, 7}},
               {'4', {5, 5, 7, 1, 1}}, {'5', {7, 4, 7, 1, 7}}, {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 1, 1}},
               {'8', {7, 5, 7, 5, 7}}, {'9', {7, 5, 7, 1, 7}}, {'.', {0, 0, 0, 0, 2}}, {'e', {0, 7, 7, 4, 7}},
               {'-', {0, 0, 7, 0, 0}}, {'+', {0, 2, 7, 2, 0}}};

// Draws `text` in white at (x, y) of an RGB image `width` wide, each font pixel as 2x2 pixels.
void DrawText(std::vector<uint8_t>& rgb, int width, int height, int x, int y, const std::string& text) {
  constexpr int kScale = 2;
  for (char c : text) {
    for (const auto& glyph : kGlyphs) {
      if (glyph.c != c) continue;
      for (int row = 0; row < 5; ++row)
        for (int col = 0; col < 3; ++col)
          if (glyph.rows[row] & (4 >> col))
            for (int dy = 0; dy < kScale; ++dy)
              for (int dx = 0; dx < kScale; ++dx) {
                const int px = x + col * kScale + dx, py = y + row * kScale + dy;
                if (px >= 0 && px < width && py >= 0 && py < height)
                  for (int k = 0; k < 3; ++k) rgb[(size_t(py) * width + px) * 3 + k] = 255;
              }
    }
    x += 4 * kScale;
  }
}

std::string FormatScale(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
}

}  // namespace

Heatmap ErrorHeatmap(const FloatImage& a, const FloatImage& b, double scale) {
  const size_t n = size_t(a.width) * size_t(a.height), channels = a.Channels();
  std::vector<double> error(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    double sum = 0.0;
    for (size_t c = 0; c < channels; ++c) {
      const float va = a.pixels[i * channels + c], vb = b.pixels[i * channels + c];
      const double e = Finite(va) && Finite(vb) ? double(va) - double(vb) : 0.0;
      sum += e * e;
    }
    error[i] = std::sqrt(sum);
  }
  Heatmap map;
  map.width = a.width;
  map.height = a.height + kHeatmapLegendRows;
  if (scale <= 0.0 && n > 0) {
    std::vector<double> sorted = error;
    const size_t percentile = std::min(n - 1, size_t(double(n) * 0.99));
    std::nth_element(sorted.begin(), sorted.begin() + ptrdiff_t(percentile), sorted.end());
    scale = sorted[percentile];
    if (scale <= 0.0) scale = *std::max_element(error.begin(), error.end());
  }
  if (scale <= 0.0) scale = 1.0;
  map.scale = scale;
  map.rgb.assign(size_t(map.width) * size_t(map.height) * 3, 0);
  size_t above = 0;
  for (size_t i = 0; i < n; ++i) {
    HeatmapColour(error[i] / scale, &map.rgb[i * 3]);
    above += error[i] > scale ? 1 : 0;
  }
  map.shareAboveScale = n > 0 ? double(above) / double(n) : 0.0;
  // The legend: a gap, the colour bar from 0 at the left to the scale at the right, its two labels.
  const int barTop = a.height + 2, barRows = 8, labelTop = barTop + barRows + 2;
  for (int y = barTop; y < barTop + barRows && y < map.height; ++y)
    for (int x = 0; x < map.width; ++x)
      HeatmapColour(map.width > 1 ? double(x) / double(map.width - 1) : 1.0,
                    &map.rgb[(size_t(y) * map.width + x) * 3]);
  DrawText(map.rgb, map.width, map.height, 1, labelTop, "0");
  const std::string top = FormatScale(scale);
  DrawText(map.rgb, map.width, map.height, map.width - 8 * int(top.size()) - 1, labelTop, top);
  return map;
}

void HeatmapColour(double t, uint8_t* rgb) {
  const double level = std::clamp(t, 0.0, 1.0) * 3.0;
  const double channel[3] = {std::min(level, 1.0), std::clamp(level - 1.0, 0.0, 1.0), std::clamp(level - 2.0, 0.0, 1.0)};
  for (int c = 0; c < 3; ++c) rgb[c] = uint8_t(channel[c] * 255.0 + 0.5);
}

}  // namespace ssgi
