#include "cli/output_files.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>

#include "core/error.h"

namespace ssgi::cli {
namespace {

namespace fs = std::filesystem;

// What a SIGINT or SIGTERM handler removes before the process ends: the temporaries and created
// folders of the outputs not yet committed. Fixed storage, because a signal handler may neither
// allocate nor lock; unlink and rmdir are async-signal-safe.
constexpr int kSlots = 256;
constexpr size_t kPathBytes = 4096;
enum SlotState : int { kFree = 0, kFile = 1, kFolder = 2, kFilling = 3 };
struct Slot {
  char path[kPathBytes];
  std::atomic<int> state;
};
Slot slots[kSlots];

void RemoveOnSignal(int signal) {
  for (Slot& slot : slots)
    if (slot.state.load() == kFile) ::unlink(slot.path);
  for (int i = kSlots - 1; i >= 0; --i)
    if (slots[i].state.load() == kFolder) ::rmdir(slots[i].path);
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

void InstallHandlers() {
  static const bool installed = [] {
    struct sigaction action {};
    action.sa_handler = RemoveOnSignal;
    sigemptyset(&action.sa_mask);
    for (int signal : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(signal, &action, nullptr);
    return true;
  }();
  (void)installed;
}

// A slot holding `path` for the handler, or -1 when the path is too long or every slot is taken
// (the output is then still removed on failure, only not on a signal).
int Register(const fs::path& path, SlotState kind) {
  InstallHandlers();
  const std::string text = fs::absolute(path).string();
  if (text.size() >= kPathBytes) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (!slots[i].state.compare_exchange_strong(expected, kFilling)) continue;
    std::memcpy(slots[i].path, text.c_str(), text.size() + 1);
    slots[i].state.store(kind);
    return i;
  }
  return -1;
}

void Unregister(int slot) {
  if (slot >= 0) slots[slot].state.store(kFree);
}

std::string LowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// Replaces every mention of `from` in an error's message by `to`: an error while writing a
// temporary names the output the user asked for.
std::string Renamed(std::string message, const std::string& from, const std::string& to) {
  for (size_t at = message.find(from); at != std::string::npos; at = message.find(from, at + to.size()))
    message.replace(at, from.size(), to);
  return message;
}

}  // namespace

OutputFiles::OutputFiles() = default;

OutputFiles::~OutputFiles() {
  if (committed_) return;
  for (const Output& output : outputs_) {
    std::error_code ignored;
    fs::remove(output.temporary, ignored);
    fs::remove(TemporarySibling(output.temporary), ignored);
    Unregister(output.slot);
    Unregister(output.writerSlot);
  }
}

void OutputFiles::Add(const fs::path& path, bool anyFormat) {
  if (path.empty()) throw InputError("an output file name is empty");
  Output output{path, {}, ImageFileKind::kPng, false, false, -1, -1};
  if (!anyFormat) {
    const std::string ext = LowerExtension(path);
    if (ext == ".exr") {
      output.kind = ImageFileKind::kExr;
    } else if (ext != ".png") {
      std::error_code error;
      if (fs::is_directory(path, error)) throw InputError(path, "is a directory, not an image file");
      throw InputError(path, "unsupported output format '" + ext + "' (use .png or .exr)");
    }
  }
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (status.type() == fs::file_type::directory) throw InputError(path, "is a directory, not an output file");
  output.existed = fs::exists(status);
  for (const Output& other : outputs_)
    if (fs::weakly_canonical(other.path, error) == fs::weakly_canonical(path, error))
      throw InputError(path, "is named twice as an output");
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  if (!fs::is_directory(folder, error)) throw InputError(path, "output folder " + folder.string() + " does not exist");
  // The temporary keeps the extension, which tells the image writer the format.
  output.temporary =
      folder / (".ssgi-" + std::to_string(::getpid()) + "-" + std::to_string(outputs_.size()) + "-" +
                path.filename().string());
  const int fd = ::open(output.temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw InputError(path, std::string("cannot write here: ") + std::strerror(errno));
  ::close(fd);
  output.slot = Register(output.temporary, kFile);
  output.writerSlot = Register(TemporarySibling(output.temporary), kFile);
  outputs_.push_back(std::move(output));
}

const OutputFiles::Output& OutputFiles::Find(const fs::path& path) const {
  for (const Output& output : outputs_)
    if (output.path == path) return output;
  throw std::logic_error("output not added: " + path.string());
}

ImageFileKind OutputFiles::Kind(const fs::path& path) const { return Find(path).kind; }

bool OutputFiles::Existed(const fs::path& path) const { return Find(path).existed; }

void OutputFiles::Write(const fs::path& path, const std::function<void(const fs::path&)>& write) {
  Output& output = const_cast<Output&>(Find(path));
  try {
    write(output.temporary);
  } catch (const InputError& e) {
    throw InputError(Renamed(e.what(), output.temporary.string(), path.string()));
  }
  output.written = true;
}

void OutputFiles::Commit() {
  for (const Output& output : outputs_)
    if (!output.written) throw std::logic_error("output not written: " + output.path.string());
  for (const Output& output : outputs_) {
    std::error_code error;
    fs::rename(output.temporary, output.path, error);
    if (error) throw InputError(output.path, "cannot move the written file into place: " + error.message());
    Unregister(output.slot);
    Unregister(output.writerSlot);
  }
  committed_ = true;
}

size_t RemoveStaleTemporaries(const fs::path& folder) {
  size_t removed = 0;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(folder, error)) {
    // ".ssgi-PID-N-name" (Add) and "..ssgi-PID-N-name.tmp-PID" (the image writer's sibling of it).
    const std::string name = entry.path().filename().string();
    const size_t start = name.rfind(".ssgi-", 1);
    if (start == std::string::npos || (start == 1 && name[0] != '.')) continue;
    const long pid = std::strtol(name.c_str() + start + 6, nullptr, 10);
    if (pid <= 0 || pid == ::getpid() || ::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue;
    std::error_code ignored;
    if (fs::remove(entry.path(), ignored)) ++removed;
  }
  return removed;
}

CreatedFolder::CreatedFolder(const fs::path& folder) {
  if (folder.empty()) throw InputError("the output folder name is empty");
  std::error_code error;
  const fs::file_status status = fs::status(folder, error);
  if (fs::exists(status) && !fs::is_directory(status)) throw InputError(folder, "exists and is not a folder");
  // The folders to create, outermost first.
  std::vector<fs::path> missing;
  for (fs::path p = fs::absolute(folder).lexically_normal(); !p.empty() && !fs::exists(p, error);
       p = p.parent_path()) {
    missing.insert(missing.begin(), p);
    if (p == p.parent_path()) break;
  }
  for (const fs::path& p : missing) {
    if (!fs::create_directory(p, error) || error) throw InputError(folder, "cannot create the folder: " + error.message());
    created_.push_back(p);
    Register(p, kFolder);
  }
}

CreatedFolder::~CreatedFolder() {
  for (auto p = created_.rbegin(); p != created_.rend(); ++p) {
    std::error_code ignored;
    if (!keep_) fs::remove(*p, ignored);  // only when empty
  }
  // The handler's slots for the folders: found by path, as they were registered.
  for (int i = 0; i < kSlots; ++i) {
    if (slots[i].state.load() != kFolder) continue;
    for (const fs::path& p : created_)
      if (p.string() == slots[i].path) Unregister(i);
  }
}

}  // namespace ssgi::cli
