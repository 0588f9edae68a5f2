#include "tests/port/port_exr.h"

#include <OpenImageIO/imageio.h>

#include "core/error.h"

namespace ssgi::port {

std::vector<Part> ReadExrParts(const std::filesystem::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw InputError(path, "cannot read: " + OIIO::geterror());
  std::vector<Part> parts;
  for (int subimage = 0; in->seek_subimage(subimage, 0); ++subimage) {
    const OIIO::ImageSpec& spec = in->spec();
    Part part;
    part.name = spec.get_string_attribute("oiio:subimagename");
    part.width = spec.width;
    part.height = spec.height;
    for (int c = 0; c < spec.nchannels; ++c) {
      Layer layer;
      layer.isUint = spec.channelformat(c) == OIIO::TypeDesc::UINT32;
      layer.samples.resize(size_t(spec.width) * size_t(spec.height));
      const OIIO::TypeDesc as = layer.isUint ? OIIO::TypeDesc::UINT32 : OIIO::TypeDesc::FLOAT;
      if (!in->read_image(subimage, 0, c, c + 1, as, layer.samples.data()))
        throw InputError(path, "cannot read channel " + spec.channelnames[size_t(c)] + ": " + in->geterror());
      part.channels.emplace_back(spec.channelnames[size_t(c)], std::move(layer));
    }
    parts.push_back(std::move(part));
  }
  if (parts.empty()) throw InputError(path, "holds no image");
  return parts;
}

void WriteExrParts(const std::filesystem::path& path, const std::vector<Part>& parts) {
  std::vector<OIIO::ImageSpec> specs;
  for (const Part& part : parts) {
    OIIO::ImageSpec spec(part.width, part.height, int(part.channels.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames.clear();
    for (const auto& [name, layer] : part.channels) {
      spec.channelnames.push_back(name);
      spec.channelformats.push_back(layer.isUint ? OIIO::TypeDesc::UINT32 : OIIO::TypeDesc::FLOAT);
    }
    // OpenEXR requires every part of a file to share one display window: the first part's.
    spec.full_width = parts[0].width;
    spec.full_height = parts[0].height;
    spec.attribute("compression", "zip");
    if (!part.name.empty()) spec.attribute("oiio:subimagename", part.name);
    specs.push_back(spec);
  }
  auto out = OIIO::ImageOutput::create("exr");
  if (!out) throw InputError(path, "cannot write: " + OIIO::geterror());
  for (size_t i = 0; i < parts.size(); ++i) {
    const bool opened = i == 0 ? out->open(path.string(), int(specs.size()), specs.data())
                               : out->open(path.string(), specs[i], OIIO::ImageOutput::AppendSubimage);
    if (!opened) throw InputError(path, "cannot write: " + out->geterror());
    // A pixel's channels interleaved, each in its own format (4 bytes either way).
    const Part& part = parts[i];
    const size_t pixels = size_t(part.width) * size_t(part.height), count = part.channels.size();
    std::vector<uint32_t> interleaved(pixels * count);
    for (size_t c = 0; c < count; ++c)
      for (size_t p = 0; p < pixels; ++p) interleaved[p * count + c] = part.channels[c].second.samples[p];
    if (!out->write_image(OIIO::TypeDesc::UNKNOWN, interleaved.data()))
      throw InputError(path, "cannot write: " + out->geterror());
  }
  if (!out->close()) throw InputError(path, "cannot write: " + out->geterror());
}

const Layer& FindLayer(const Part& part, const std::string& name, bool isUint, const std::filesystem::path& file) {
  for (const auto& [channelName, layer] : part.channels) {
    if (channelName != name) continue;
    if (layer.isUint != isUint)
      throw InputError(file, "layer " + name + " is " + (layer.isUint ? "uint32" : "float") + ", must be " +
                                 (isUint ? "uint32" : "float"));
    return layer;
  }
  throw InputError(file, "has no layer " + name);
}

}  // namespace ssgi::port
