#include "core/image_io.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstring>

#include <OpenImageIO/imageio.h>

#include "core/check.h"
#include "core/error.h"

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
// formats, interleaved.
void InterleaveRows(const ExrPart& part, size_t yBegin, size_t yEnd, std::vector<uint32_t>& interleaved) {
  const size_t count = part.channels.size();
  const size_t width = size_t(part.width);
  interleaved.resize(width * (yEnd - yBegin) * count);
  for (size_t c = 0; c < count; ++c) {
    const auto* source = static_cast<const uint32_t*>(part.channels[c].data);
    for (size_t y = yBegin; y < yEnd; ++y)
      for (size_t x = 0; x < width; ++x)
        interleaved[((y - yBegin) * width + x) * count + c] = source[y * part.channels[c].rowStride + x];
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

size_t ExrSampleBytes(const fs::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw InputError(path, "cannot read image: " + OIIO::geterror());
  if (std::string(in->format_name()) != "openexr") throw InputError(path, "not an EXR file");
  size_t bytes = 0;
  for (int subimage = 0; in->seek_subimage(subimage, 0); ++subimage) {
    const OIIO::ImageSpec& spec = in->spec();
    bytes += size_t(std::max(spec.width, 0)) * size_t(std::max(spec.height, 0)) * size_t(std::max(spec.nchannels, 0)) *
             sizeof(uint32_t);
  }
  return bytes;
}

ExrFile ReadExrFile(const fs::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw InputError(path, "cannot read image: " + OIIO::geterror());
  if (std::string(in->format_name()) != "openexr") throw InputError(path, "not an EXR file");
  ExrFile file;
  for (int subimage = 0; in->seek_subimage(subimage, 0); ++subimage) {
    const OIIO::ImageSpec& spec = in->spec();
    if (subimage == 0) {
      for (const OIIO::ParamValue& attribute : spec.extra_attribs)
        if (attribute.type() == OIIO::TypeDesc::STRING && attribute.name().string().rfind("oiio:", 0) != 0)
          file.metadata[attribute.name().string()] = attribute.get_string();
    }
    const std::string part = spec.get_string_attribute("oiio:subimagename");
    for (int c = 0; c < spec.nchannels; ++c) {
      const OIIO::TypeDesc format = spec.channelformat(c);
      ExrLayer layer{part, spec.channelnames[size_t(c)], spec.width, spec.height, format == OIIO::TypeDesc::UINT32, {}};
      if (!layer.isUint && format != OIIO::TypeDesc::FLOAT && format != OIIO::TypeDesc::HALF)
        throw InputError(path, "channel '" + layer.name + "' is " + format.c_str() + ", not uint32, half or float");
      layer.samples.resize(size_t(spec.width) * size_t(spec.height));
      const OIIO::TypeDesc readAs = layer.isUint ? OIIO::TypeDesc::UINT32 : OIIO::TypeDesc::FLOAT;
      if (!in->read_image(subimage, 0, c, c + 1, readAs, layer.samples.data()))
        throw InputError(path, "cannot read channel '" + layer.name + "': " + in->geterror());
      file.layers.push_back(std::move(layer));
    }
  }
  if (file.layers.empty()) throw InputError(path, "the EXR holds no channels");
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
