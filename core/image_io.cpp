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

// Writes through `write` into a temporary sibling of `path`, then renames it into place.
template <class WriteFn>
void WriteAtomically(const fs::path& path, const OIIO::ImageSpec& spec, WriteFn&& write) {
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const fs::path temporary = folder / ("." + path.filename().string() + ".tmp-" + std::to_string(::getpid()));
  auto fail = [&](const std::string& why) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw InputError(path, "cannot write image: " + why);
  };
  auto out = OIIO::ImageOutput::create(LowerExtension(path).substr(1));
  if (!out) fail(OIIO::geterror());
  if (!out->open(temporary.string(), spec)) fail(out->geterror());
  if (!write(*out)) fail(out->geterror());
  if (!out->close()) fail(out->geterror());
  std::error_code error;
  fs::rename(temporary, path, error);
  if (error) fail(error.message());
}

}  // namespace

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
  const OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  WriteAtomically(path, spec, [&](OIIO::ImageOutput& out) { return out.write_image(OIIO::TypeDesc::UINT8, rgb.data()); });
}

void WriteExr(const fs::path& path, int width, int height, const std::vector<ExrChannel>& channels) {
  const int count = int(channels.size());
  OIIO::ImageSpec spec(width, height, count, OIIO::TypeDesc::FLOAT);
  spec.channelnames.clear();
  for (const ExrChannel& c : channels) {
    spec.channelnames.push_back(c.name);
    spec.channelformats.push_back(c.isUint ? OIIO::TypeDesc::UINT32 : OIIO::TypeDesc::FLOAT);
  }
  spec.attribute("compression", "zip");
  // Every sample is 4 bytes, so a pixel is `count` 4-byte words in the channels' native formats.
  std::vector<uint32_t> interleaved(size_t(width) * size_t(height) * size_t(count));
  for (int c = 0; c < count; ++c) {
    const auto* source = static_cast<const uint32_t*>(channels[c].data);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        interleaved[(size_t(y) * width + x) * count + c] = source[size_t(y) * channels[c].rowStride + x];
  }
  WriteAtomically(path, spec, [&](OIIO::ImageOutput& out) {
    return out.write_image(OIIO::TypeDesc::UNKNOWN, interleaved.data());
  });
}

}  // namespace ssgi
