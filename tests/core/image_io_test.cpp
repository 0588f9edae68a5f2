// EXR reading (core/image_io.h): every part decoded once in bands of rows on all threads, the same
// layers at any thread count; half channels widened, tiled parts and odd sizes; channels left out
// by a filter listed without samples.
#include "core/image_io.h"

#include <OpenImageIO/imageio.h>

#include <catch2/catch.hpp>
#include <cstring>
#include <random>

#include "core/parallel.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;

// A part of `channels` channels, every third one uint32, of random bits (NaNs and denormals
// among the floats).
struct SourcePart {
  std::string name;
  int width, height;
  std::vector<std::string> names;
  std::vector<bool> isUint;
  std::vector<std::vector<uint32_t>> samples;
};

SourcePart RandomPart(const std::string& name, int width, int height, int channels, uint32_t seed) {
  std::mt19937 random(seed);
  SourcePart part{name, width, height, {}, {}, {}};
  for (int c = 0; c < channels; ++c) {
    part.names.push_back("layer" + std::to_string(c) + ".X");
    part.isUint.push_back(c % 3 == 0);
    std::vector<uint32_t> values(size_t(width) * size_t(height));
    for (uint32_t& value : values) value = random();
    part.samples.push_back(std::move(values));
  }
  return part;
}

void WriteParts(const fs::path& path, const std::vector<SourcePart>& parts) {
  std::vector<ExrPart> exr;
  for (const SourcePart& part : parts) {
    ExrPart out{part.name, part.width, part.height, {}};
    for (size_t c = 0; c < part.names.size(); ++c)
      out.channels.push_back({part.names[c], part.isUint[c], part.samples[c].data(), size_t(part.width)});
    exr.push_back(std::move(out));
  }
  WriteExrParts(path, exr, {{"test:note", "parts"}});
}

// How many of `file`'s layers hold exactly the samples of `parts` (every layer must be there).
size_t LayersAsWritten(const ExrFile& file, const std::vector<SourcePart>& parts) {
  size_t same = 0;
  for (const SourcePart& part : parts) {
    for (size_t c = 0; c < part.names.size(); ++c) {
      const ExrLayer* layer = file.Find(part.name, part.names[c]);
      REQUIRE(layer != nullptr);
      CHECK(layer->isUint == part.isUint[c]);
      if (layer->samples == part.samples[c]) ++same;
    }
  }
  return same;
}

TEST_CASE("EXR files: a multi-part file reads the same layers at 1 and 2 threads", "[image_io]") {
  test::ScratchDir dir("image-io-parts");
  // A part of many channels over several bands, one whose height is no multiple of a band, and
  // one of a single pixel.
  const std::vector<SourcePart> parts = {RandomPart("frame", 67, 101, 40, 1), RandomPart("tall", 5, 333, 3, 2),
                                         RandomPart("dot", 1, 1, 2, 3)};
  WriteParts(dir / "parts.exr", parts);
  std::vector<ExrFile> reads;
  for (int threads : {1, 2}) {
    const ThreadLimit limit(threads);
    reads.push_back(ReadExrFile(dir / "parts.exr"));
  }
  for (const ExrFile& file : reads) {
    CHECK(file.layers.size() == 45);
    CHECK(LayersAsWritten(file, parts) == 45);
    CHECK(file.metadata.at("test:note") == "parts");
  }
  // In file order: the parts in order, each part's channels in order.
  for (size_t i = 0; i < reads[0].layers.size(); ++i) {
    CHECK(reads[0].layers[i].part == reads[1].layers[i].part);
    CHECK(reads[0].layers[i].name == reads[1].layers[i].name);
  }

  // A filter reads only what it accepts; the rest is listed without samples, and a part none of
  // whose channels it accepts is not decoded.
  const ExrChannelFilter some = [](const std::string& part, const std::string& name) {
    return part == "frame" && (name == "layer7.X" || name == "layer9.X");
  };
  CHECK(ExrSampleBytes(dir / "parts.exr", some) == 2 * 67 * 101 * 4);
  CHECK(ExrSampleBytes(dir / "parts.exr") == (40 * 67 * 101 + 3 * 5 * 333 + 2) * 4);
  const ExrFile filtered = ReadExrFile(dir / "parts.exr", some);
  REQUIRE(filtered.layers.size() == 45);
  for (const ExrLayer& layer : filtered.layers) {
    CAPTURE(layer.part, layer.name);
    if (some(layer.part, layer.name)) {
      CHECK(layer.samples == reads[0].Find(layer.part, layer.name)->samples);
    } else {
      CHECK(layer.samples.empty());
      CHECK(layer.width == reads[0].Find(layer.part, layer.name)->width);
    }
  }
}

TEST_CASE("EXR files: half channels are widened exactly, tiled parts are read whole", "[image_io]") {
  test::ScratchDir dir("image-io-half");
  const fs::path path = dir / "mixed.exr";
  constexpr int kWidth = 37, kHeight = 70;
  // Scanlines of a half, a float and a uint channel in one file; 16x16 tiles of a float in another.
  OIIO::ImageSpec mixed(kWidth, kHeight, 3, OIIO::TypeDesc::FLOAT);
  mixed.channelnames = {"h", "f", "u"};
  mixed.channelformats = {OIIO::TypeDesc::HALF, OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::UINT32};
  mixed.attribute("oiio:subimagename", "mixed");
  mixed.attribute("compression", "piz");
  OIIO::ImageSpec tiled(kWidth, kHeight, 1, OIIO::TypeDesc::FLOAT);
  tiled.channelnames = {"t"};
  tiled.tile_width = tiled.tile_height = 16;
  // Pixels of the first file interleaved as it holds them: 2 + 4 + 4 bytes.
  std::vector<unsigned char> pixels(size_t(kWidth) * kHeight * 10);
  std::vector<float> halves, floats, tiles;
  std::vector<uint32_t> uints;
  for (int i = 0; i < kWidth * kHeight; ++i) {
    // Half bits 0x7C00 and up are infinities and NaNs, left out; denormals are among the rest.
    const uint16_t halfBits = uint16_t((i * 37) % 0x7C00);
    float widened;
    OIIO::convert_pixel_values(OIIO::TypeDesc::HALF, &halfBits, OIIO::TypeDesc::FLOAT, &widened, 1);
    halves.push_back(widened);
    floats.push_back(float(i) * 0.25f - 100.0f);
    uints.push_back(uint32_t(i) * 2654435761u);
    tiles.push_back(float(i % 97));
    std::memcpy(&pixels[size_t(i) * 10], &halfBits, 2);
    std::memcpy(&pixels[size_t(i) * 10 + 2], &floats.back(), 4);
    std::memcpy(&pixels[size_t(i) * 10 + 6], &uints.back(), 4);
  }
  const auto write = [](const fs::path& file, const OIIO::ImageSpec& spec, OIIO::TypeDesc format, const void* data) {
    auto out = OIIO::ImageOutput::create("exr");
    REQUIRE(out);
    const bool written = out->open(file.string(), spec) && out->write_image(format, data) && out->close();
    INFO(out->geterror());
    REQUIRE(written);
  };
  write(path, mixed, OIIO::TypeDesc::UNKNOWN, pixels.data());
  write(dir / "tiled.exr", tiled, OIIO::TypeDesc::FLOAT, tiles.data());
  for (int threads : {1, 2}) {
    const ThreadLimit limit(threads);
    const ExrFile file = ReadExrFile(path);
    const ExrFile tiledFile = ReadExrFile(dir / "tiled.exr");
    REQUIRE(file.layers.size() == 3);
    const ExrLayer* h = file.Find("mixed", "h");
    const ExrLayer* f = file.Find("mixed", "f");
    const ExrLayer* u = file.Find("mixed", "u");
    const ExrLayer* t = tiledFile.Find("", "t");
    REQUIRE((h && f && u && t));
    CHECK_FALSE(h->isUint);
    CHECK(u->isUint);
    size_t same = 0;
    for (size_t i = 0; i < size_t(kWidth * kHeight); ++i)
      same +=
          h->Float(i) == halves[i] && f->Float(i) == floats[i] && u->samples[i] == uints[i] && t->Float(i) == tiles[i];
    CHECK(same == size_t(kWidth * kHeight));
  }
}

}  // namespace
}  // namespace ssgi
