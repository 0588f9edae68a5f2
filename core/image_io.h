// Image files, all through OpenImageIO (DESIGN.md §8). Writes are atomic: the image goes to a
// temporary file in the destination folder, which is renamed over the destination only when
// complete, so a failed or interrupted write never leaves a half-written file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ssgi {

enum class ImageFileKind { kPng, kExr };

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

}  // namespace ssgi
