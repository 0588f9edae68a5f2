// The EXR files the port reads and writes: an ssgi dump's layers in, the port's layers out, under
// the dump's names (docs/pipeline.md). Small on purpose: when core grows a reader and writer of
// multi-part dumps (issue 13), these two functions give way to it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace ssgi::port {

// One channel: its samples' 4-byte words as stored (uint32 integers or float bits), top row first.
struct Layer {
  bool isUint = false;
  std::vector<uint32_t> samples;
};

// One part (OpenImageIO subimage) of an EXR: its name ("" when unnamed: a single-part file), size and
// channels by name, in the order written.
struct Part {
  std::string name;
  int width = 0, height = 0;
  std::vector<std::pair<std::string, Layer>> channels;
};

// Every part of `path`; throws InputError naming the file when it cannot be read.
std::vector<Part> ReadExrParts(const std::filesystem::path& path);
// Writes the parts in order (zip compression); throws InputError naming the file on failure.
void WriteExrParts(const std::filesystem::path& path, const std::vector<Part>& parts);

// The channel `name` of `part`, uint32 or float as `isUint` says; throws InputError naming `file`
// when it is missing or of the other type.
const Layer& FindLayer(const Part& part, const std::string& name, bool isUint, const std::filesystem::path& file);

}  // namespace ssgi::port
