// Image files, all through OpenImageIO (docs/design.md §8). Writes are atomic: the image goes to a
// temporary file in the destination folder, which is renamed over the destination only when
// complete, so a failed or interrupted write never leaves a half-written file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace ssgi {

enum class ImageFileKind { kPng, kExr };

// The temporary sibling an atomic write of `path` goes through before it is renamed into place.
std::filesystem::path TemporarySibling(const std::filesystem::path& path);

// The kind of image a path asks for by its extension (.png or .exr, any case). Throws InputError
// naming the path for any other extension, and when its folder is missing or not writable, so a
// render fails before it starts rather than after.
ImageFileKind CheckOutputPath(const std::filesystem::path& path);

// 8-bit RGB, interleaved rows, top row first.
void WritePng(const std::filesystem::path& path, int width, int height, const std::vector<uint8_t>& rgb);

// One channel of a multi-channel EXR: `name` as it appears in the file ("R", "albedo.R",
// "gbuffer.word0"); float32 or uint32 samples read from rows `rowStride` elements apart.
struct ExrChannel {
  std::string name;
  bool isUint = false;
  const void* data = nullptr;
  size_t rowStride = 0;  // in elements of 4 bytes
};

void WriteExr(const std::filesystem::path& path, int width, int height, const std::vector<ExrChannel>& channels);

// One part of a multi-part EXR (an OpenImageIO subimage): its name, its size and its channels.
struct ExrPart {
  std::string name;
  int width = 0, height = 0;
  std::vector<ExrChannel> channels;
};

// Writes the parts in order, with `metadata` as string attributes of the first part.
void WriteExrParts(const std::filesystem::path& path, const std::vector<ExrPart>& parts,
                   const std::map<std::string, std::string>& metadata = {});

// One channel of an EXR as it is stored: its 4-byte samples' bits, unconverted (a uint32 channel's
// integers, a float channel's float bits; half channels are widened to float), top row first.
struct ExrLayer {
  std::string part;  // the part's name ("" for an unnamed single part)
  std::string name;
  int width = 0, height = 0;
  bool isUint = false;
  std::vector<uint32_t> samples;  // width * height; empty when ReadExrFile was told to skip the channel
  float Float(size_t i) const;    // sample i of a float channel
};

struct ExrFile {
  std::vector<ExrLayer> layers;  // every channel of every part, in file order
  std::map<std::string, std::string> metadata;  // the first part's string attributes but OIIO's own
  // The channel `name` of part `part`, or nullptr.
  const ExrLayer* Find(const std::string& part, const std::string& name) const;
};

// Which channels' samples to read, by part name and channel name; an empty filter reads them all.
using ExrChannelFilter = std::function<bool(const std::string& part, const std::string& name)>;

// The bytes ReadExrFile would hold for the file's samples (those `read` accepts), from its headers
// alone: what a command checks against its memory budget before reading. Throws InputError as
// ReadExrFile does.
size_t ExrSampleBytes(const std::filesystem::path& path, const ExrChannelFilter& read = {});

// Reads every channel of every part: the layers in file order, with the samples of those `read`
// accepts (all without a filter). Each part is decoded once, in bands of rows on all threads
// (core/parallel.h), each thread with an ImageInput of its own; the bytes read do not depend on the
// thread count. Throws InputError naming the file when it cannot be read, is not an EXR, or holds
// deep data or a channel type other than uint32, half and float.
ExrFile ReadExrFile(const std::filesystem::path& path, const ExrChannelFilter& read = {});
// Writes what ReadExrFile read (half channels as float): a part per distinct part name, in order of
// first appearance, each part's channels in file order.
void WriteExrFile(const std::filesystem::path& path, const ExrFile& file);

}  // namespace ssgi
