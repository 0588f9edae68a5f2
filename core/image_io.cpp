#include "core/image_io.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <mutex>

#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;

std::string LowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// Writes the subimages `specs` through `write` (called with the output opened on subimage i, for
// each i) into a temporary sibling of `path`, then renames it into place.
template <class WriteFn>
void WriteAtomically(const fs::path& path, const std::vector<OIIO::ImageSpec>& specs, WriteFn&& write) {
  const fs::path temporary = TemporarySibling(path);
  auto fail = [&](const std::string& why) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw InputError(path, "cannot write image: " + why);
  };
  // OpenEXR compresses the blocks of each write on its own pool: as many threads as ParallelFor may
  // use (ReadExrFile leaves the pool at none).
  OIIO::attribute("exr_threads", int(ParallelThreads()));
  auto out = OIIO::ImageOutput::create(LowerExtension(path).substr(1));
  if (!out) fail(OIIO::geterror());
  for (size_t i = 0; i < specs.size(); ++i) {
    const bool opened = i == 0 ? out->open(temporary.string(), int(specs.size()), specs.data())
                               : out->open(temporary.string(), specs[i], OIIO::ImageOutput::AppendSubimage);
    if (!opened) fail(out->geterror());
    if (!write(*out, i)) fail(out->geterror());
  }
  if (!out->close()) fail(out->geterror());
  std::error_code error;
  fs::rename(temporary, path, error);
  if (error) fail(error.message());
}

// Rows [yBegin, yEnd) of the part, each pixel `count` 4-byte words in the channels' native
// formats, interleaved: row by row, so that each row's channels are gathered while it is in cache.
void InterleaveRows(const ExrPart& part, size_t yBegin, size_t yEnd, std::vector<uint32_t>& interleaved) {
  const size_t count = part.channels.size();
  const size_t width = size_t(part.width);
  interleaved.resize(width * (yEnd - yBegin) * count);
  for (size_t y = yBegin; y < yEnd; ++y) {
    uint32_t* row = interleaved.data() + (y - yBegin) * width * count;
    for (size_t c = 0; c < count; ++c) {
      const auto* source = static_cast<const uint32_t*>(part.channels[c].data) + y * part.channels[c].rowStride;
      for (size_t x = 0; x < width; ++x) row[x * count + c] = source[x];
    }
  }
}

// Writes the part a band of rows at a time, so a dump of many layers never holds a whole
// interleaved copy of them.
bool WritePartRows(OIIO::ImageOutput& out, const ExrPart& part) {
  constexpr size_t kBandRows = 64;
  std::vector<uint32_t> band;
  for (size_t y = 0; y < size_t(part.height); y += kBandRows) {
    const size_t yEnd = std::min(y + kBandRows, size_t(part.height));
    InterleaveRows(part, y, yEnd, band);
    if (!out.write_scanlines(int(y), int(yEnd), 0, OIIO::TypeDesc::UNKNOWN, band.data())) return false;
  }
  return true;
}

OIIO::ImageSpec PartSpec(const ExrPart& part) {
  OIIO::ImageSpec spec(part.width, part.height, int(part.channels.size()), OIIO::TypeDesc::FLOAT);
  spec.channelnames.clear();
  for (const ExrChannel& c : part.channels) {
    spec.channelnames.push_back(c.name);
    spec.channelformats.push_back(c.isUint ? OIIO::TypeDesc::UINT32 : OIIO::TypeDesc::FLOAT);
  }
  spec.attribute("compression", "zip");
  if (!part.name.empty()) spec.attribute("oiio:subimagename", part.name);
  return spec;
}

// The file opened for reading, checked to be an EXR. Each reader sets OpenEXR's own thread pool
// to none: ReadExrFile decodes its bands on the threads of ParallelFor, one ImageInput each.
std::unique_ptr<OIIO::ImageInput> OpenExr(const fs::path& path) {
  OIIO::attribute("exr_threads", -1);
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw InputError(path, "cannot read image: " + OIIO::geterror());
  if (std::string(in->format_name()) != "openexr") throw InputError(path, "not an EXR file");
  return in;
}

// An open input and the band buffer its thread decodes into.
struct ExrReader {
  std::unique_ptr<OIIO::ImageInput> input;
  std::vector<unsigned char> buffer;
};

// Readers of one file for the threads of a ParallelFor: an ImageInput serialises the reads made
// through it, so each thread takes one of its own, opened on first need and handed back for the
// next band.
class ExrInputs {
 public:
  explicit ExrInputs(const fs::path& path) : path_(path) {}

  ExrReader Take() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (!idle_.empty()) {
        ExrReader reader = std::move(idle_.back());
        idle_.pop_back();
        return reader;
      }
    }
    return {OpenExr(path_), {}};
  }

  void Give(ExrReader reader) {
    const std::lock_guard<std::mutex> lock(mutex_);
    idle_.push_back(std::move(reader));
  }

 private:
  const fs::path& path_;
  std::mutex mutex_;
  std::vector<ExrReader> idle_;
};

// Where each channel ReadExrFile keeps lies in a pixel of a part as read natively.
struct ExrPartLayout {
  int subimage;
  int y;  // the data window's first row
  int width, height, channelCount;
  bool tiled;
  size_t pixelBytes;  // all channels, each in its own format
  struct Channel {
    size_t layer;   // index into ExrFile::layers
    size_t offset;  // bytes into the pixel
    bool isHalf;
  };
  std::vector<Channel> channels;
};

// Row y of the part, read natively into `pixels`, into the layers' samples.
void Deinterleave(const ExrPartLayout& part, const unsigned char* pixels, size_t y, std::vector<ExrLayer>& layers) {
  const size_t width = size_t(part.width);
  for (const ExrPartLayout::Channel& channel : part.channels) {
    uint32_t* out = layers[channel.layer].samples.data() + y * width;
    const unsigned char* in = pixels + channel.offset;
    if (channel.isHalf) {
      // Gathered, then widened exactly by OpenImageIO (whose half type needs a library of its own).
      std::vector<uint16_t> halves(width);
      for (size_t x = 0; x < width; ++x) std::memcpy(&halves[x], in + x * part.pixelBytes, sizeof(uint16_t));
      OIIO::convert_pixel_values(OIIO::TypeDesc::HALF, halves.data(), OIIO::TypeDesc::FLOAT, out, int(width));
    } else {
      for (size_t x = 0; x < width; ++x) std::memcpy(&out[x], in + x * part.pixelBytes, sizeof(uint32_t));
    }
  }
}

}  // namespace

fs::path TemporarySibling(const fs::path& path) {
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  return folder / ("." + path.filename().string() + ".tmp-" + std::to_string(::getpid()));
}

ImageFileKind CheckOutputPath(const fs::path& path) {
  const std::string ext = LowerExtension(path);
  ImageFileKind kind;
  if (ext == ".png") {
    kind = ImageFileKind::kPng;
  } else if (ext == ".exr") {
    kind = ImageFileKind::kExr;
  } else {
    throw InputError(path, "unsupported output format '" + ext + "' (use .png or .exr)");
  }
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code error;
  if (!fs::is_directory(folder, error)) throw InputError(path, "output folder " + folder.string() + " does not exist");
  if (::access(folder.c_str(), W_OK) != 0) throw InputError(path, "output folder " + folder.string() + " is not writable");
  if (fs::is_directory(path, error)) throw InputError(path, "output path is a folder");
  return kind;
}

void WritePng(const fs::path& path, int width, int height, const std::vector<uint8_t>& rgb) {
  SSGI_CHECK_EQ(rgb.size(), size_t(width) * size_t(height) * 3);
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  // Deflate level 3 with the "up" row filter instead of libpng's level 6 trying every filter: the
  // file is written several times faster for 14-20% more bytes (docs/perf-log.md); the pixels are
  // the same.
  spec.attribute("png:compressionLevel", 3);
  spec.attribute("png:filter", 0x20);  // PNG_FILTER_UP
  WriteAtomically(path, {spec}, [&](OIIO::ImageOutput& out, size_t) {
    return out.write_image(OIIO::TypeDesc::UINT8, rgb.data());
  });
}

void WriteExr(const fs::path& path, int width, int height, const std::vector<ExrChannel>& channels) {
  WriteExrParts(path, {ExrPart{"", width, height, channels}});
}

void WriteExrParts(const fs::path& path, const std::vector<ExrPart>& parts,
                   const std::map<std::string, std::string>& metadata) {
  SSGI_CHECK(!parts.empty());
  std::vector<OIIO::ImageSpec> specs;
  for (const ExrPart& part : parts) {
    specs.push_back(PartSpec(part));
    // OpenEXR requires one display window for all parts: the first part's; each part's own pixels
    // are its data window.
    specs.back().full_width = parts[0].width;
    specs.back().full_height = parts[0].height;
  }
  for (const auto& [key, value] : metadata) specs[0].attribute(key, value);
  WriteAtomically(path, specs, [&](OIIO::ImageOutput& out, size_t i) { return WritePartRows(out, parts[i]); });
}

float ExrLayer::Float(size_t i) const {
  float value;
  std::memcpy(&value, &samples[i], sizeof(value));
  return value;
}

const ExrLayer* ExrFile::Find(const std::string& part, const std::string& name) const {
  for (const ExrLayer& layer : layers)
    if (layer.part == part && layer.name == name) return &layer;
  return nullptr;
}

size_t ExrSampleBytes(const fs::path& path, const ExrChannelFilter& read) {
  auto in = OpenExr(path);
  size_t bytes = 0;
  for (int subimage = 0; in->seek_subimage(subimage, 0); ++subimage) {
    const OIIO::ImageSpec& spec = in->spec();
    const std::string part = spec.get_string_attribute("oiio:subimagename");
    for (int c = 0; c < spec.nchannels; ++c)
      if (!read || read(part, spec.channelnames[size_t(c)]))
        bytes += size_t(std::max(spec.width, 0)) * size_t(std::max(spec.height, 0)) * sizeof(uint32_t);
  }
  return bytes;
}

ExrFile ReadExrFile(const fs::path& path, const ExrChannelFilter& read) {
  ExrInputs inputs(path);
  ExrReader first = inputs.Take();
  ExrFile file;
  std::vector<ExrPartLayout> parts;
  for (int subimage = 0; first.input->seek_subimage(subimage, 0); ++subimage) {
    const OIIO::ImageSpec& spec = first.input->spec();
    if (subimage == 0) {
      for (const OIIO::ParamValue& attribute : spec.extra_attribs)
        if (attribute.type() == OIIO::TypeDesc::STRING && attribute.name().string().rfind("oiio:", 0) != 0)
          file.metadata[attribute.name().string()] = attribute.get_string();
    }
    const std::string part = spec.get_string_attribute("oiio:subimagename");
    if (spec.deep) throw InputError(path, "part '" + part + "' holds deep data, not one sample per pixel");
    ExrPartLayout layout{
        subimage, spec.y, spec.width, spec.height, spec.nchannels, spec.tile_width > 0, spec.pixel_bytes(true), {}};
    size_t offset = 0;
    for (int c = 0; c < spec.nchannels; ++c) {
      const OIIO::TypeDesc format = spec.channelformat(c);
      ExrLayer layer{part, spec.channelnames[size_t(c)], spec.width, spec.height, format == OIIO::TypeDesc::UINT32, {}};
      if (!layer.isUint && format != OIIO::TypeDesc::FLOAT && format != OIIO::TypeDesc::HALF)
        throw InputError(path, "channel '" + layer.name + "' is " + format.c_str() + ", not uint32, half or float");
      if (!read || read(part, layer.name)) {
        layer.samples.resize(size_t(spec.width) * size_t(spec.height));
        layout.channels.push_back({file.layers.size(), offset, format == OIIO::TypeDesc::HALF});
      }
      offset += format.size();
      file.layers.push_back(std::move(layer));
    }
    parts.push_back(std::move(layout));
  }
  if (file.layers.empty()) throw InputError(path, "the EXR holds no channels");
  inputs.Give(std::move(first));

  // Fixed bands of rows, a multiple of every lossless compression's block (zip 16 rows, piz 32,
  // none, rle and zips 1), so no block is decoded twice; a tiled part is read whole.
  constexpr int kBandRows = 32;
  struct Band {
    size_t part;
    int yBegin, yEnd;  // rows of the part's data window, from 0
  };
  std::vector<Band> bands;
  for (size_t p = 0; p < parts.size(); ++p) {
    if (parts[p].channels.empty()) continue;
    const int step = parts[p].tiled ? std::max(parts[p].height, 1) : kBandRows;
    for (int y = 0; y < parts[p].height; y += step) bands.push_back({p, y, std::min(y + step, parts[p].height)});
  }
  std::vector<std::string> errors(bands.size());
  ParallelFor("read EXR", bands.size(), [&](size_t i) {
    const Band& band = bands[i];
    const ExrPartLayout& part = parts[band.part];
    try {
      ExrReader reader = inputs.Take();
      std::vector<unsigned char>& buffer = reader.buffer;
      const size_t rowBytes = size_t(part.width) * part.pixelBytes;
      buffer.resize(rowBytes * size_t(band.yEnd - band.yBegin));
      // Every channel in its native format: one decode of the part's blocks for all of them.
      OIIO::ImageInput& in = *reader.input;
      const bool ok =
          part.tiled ? in.read_image(part.subimage, 0, 0, part.channelCount, OIIO::TypeDesc::UNKNOWN, buffer.data())
                     : in.read_scanlines(part.subimage, 0, part.y + band.yBegin, part.y + band.yEnd, 0, 0,
                                         part.channelCount, OIIO::TypeDesc::UNKNOWN, buffer.data());
      if (!ok) {
        errors[i] = in.geterror();
        if (errors[i].empty()) errors[i] = "unknown error";
        return;
      }
      for (int y = band.yBegin; y < band.yEnd; ++y)
        Deinterleave(part, buffer.data() + size_t(y - band.yBegin) * rowBytes, size_t(y), file.layers);
      inputs.Give(std::move(reader));
    } catch (const std::exception& e) {
      errors[i] = e.what();
    }
  });
  for (size_t i = 0; i < bands.size(); ++i) {
    if (errors[i].empty()) continue;
    const ExrPartLayout& part = parts[bands[i].part];
    throw InputError(path, "cannot read part '" + file.layers[part.channels.front().layer].part + "' rows " +
                               std::to_string(bands[i].yBegin) + "-" + std::to_string(bands[i].yEnd - 1) + ": " +
                               errors[i]);
  }
  return file;
}

void WriteExrFile(const fs::path& path, const ExrFile& file) {
  std::vector<ExrPart> parts;
  for (const ExrLayer& layer : file.layers) {
    auto part = std::find_if(parts.begin(), parts.end(), [&](const ExrPart& p) { return p.name == layer.part; });
    if (part == parts.end()) part = parts.insert(parts.end(), ExrPart{layer.part, layer.width, layer.height, {}});
    if (part->width != layer.width || part->height != layer.height)
      throw InputError(path, "channel '" + layer.name + "' is not the size of its part '" + layer.part + "'");
    part->channels.push_back({layer.name, layer.isUint, layer.samples.data(), size_t(layer.width)});
  }
  if (parts.empty()) throw InputError(path, "no channels to write");
  WriteExrParts(path, parts, file.metadata);
}

}  // namespace ssgi
