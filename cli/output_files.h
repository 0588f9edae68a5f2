// All or nothing: the files a command writes appear together when it succeeds, and none of them when
// it fails, is interrupted (SIGINT, SIGTERM) or runs out of disk. Each output is written to a
// temporary sibling of its path and renamed into place only after every output has been written.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/image_io.h"

namespace ssgi::cli {

class OutputFiles {
 public:
  OutputFiles();
  ~OutputFiles();  // removes what was not committed
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;

  // Checks `path` as an output before any work is done (a name given, not a directory, a .png or
  // .exr unless `anyFormat`, its folder present and writable) and reserves a temporary sibling by
  // creating it. Throws InputError naming `path`.
  void Add(const std::filesystem::path& path, bool anyFormat = false);
  // The kind of image `path` is (it must have been added as an image).
  ImageFileKind Kind(const std::filesystem::path& path) const;
  // Writes `path`'s content through `write`, which is given the temporary to write; errors name
  // `path`, not the temporary.
  void Write(const std::filesystem::path& path, const std::function<void(const std::filesystem::path&)>& write);
  // Renames every temporary onto its path (each must have been written).
  void Commit();
  // Whether `path` existed before this command: the caller may say it was overwritten.
  bool Existed(const std::filesystem::path& path) const;

 private:
  struct Output {
    std::filesystem::path path, temporary;
    ImageFileKind kind = ImageFileKind::kPng;
    bool existed = false;
    bool written = false;
    // In the signal handler's list: the temporary, and the image writer's own temporary of it.
    int slot = -1, writerSlot = -1;
  };
  const Output& Find(const std::filesystem::path& path) const;
  std::vector<Output> outputs_;
  bool committed_ = false;
};

// Removes from `folder` the temporaries of OutputFiles whose process is gone: a process killed with
// SIGKILL (which no handler sees) leaves its temporary behind. Returns how many it removed.
size_t RemoveStaleTemporaries(const std::filesystem::path& folder);

// A folder a command creates for its outputs: removed again, when it created it, unless Keep() was
// called, if it is then empty.
class CreatedFolder {
 public:
  explicit CreatedFolder(const std::filesystem::path& folder);
  ~CreatedFolder();
  CreatedFolder(const CreatedFolder&) = delete;
  CreatedFolder& operator=(const CreatedFolder&) = delete;
  void Keep() { keep_ = true; }

 private:
  std::vector<std::filesystem::path> created_;  // deepest last
  bool keep_ = false;
};

}  // namespace ssgi::cli
