#include "core/system_memory.h"

#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

#include "core/error.h"

namespace ssgi {
namespace {

// Field `field` (0 the size, 1 the resident set, 2 its file-backed part: RssFile + RssShmem) of
// /proc/self/statm, in bytes; 0 where unknown.
size_t StatmBytes(int field) {
  std::ifstream statm("/proc/self/statm");
  size_t pages[3] = {};
  if (!(statm >> pages[0] >> pages[1] >> pages[2])) return 0;
  return pages[field] * size_t(::sysconf(_SC_PAGESIZE));
}

// The number in a cgroup file ("max" and unreadable files: nullopt).
std::optional<size_t> ReadCgroupNumber(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string text;
  if (!(in >> text) || text == "max") return std::nullopt;
  char* end = nullptr;
  const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
  if (end == text.c_str() || *end != '\0') return std::nullopt;
  return size_t(value);
}

// The smallest headroom (limit - usage) of the cgroup folder `folder` and its ancestors up to
// `root`, reading the files `limitName` and `usageName`.
size_t HeadroomUpTo(std::filesystem::path folder, const std::filesystem::path& root, const char* limitName,
                    const char* usageName) {
  // Limits above this are "no limit" (cgroup v1 reports unlimited as a page-rounded LONG_MAX).
  constexpr size_t kUnlimited = size_t(1) << 60;
  size_t headroom = 0;
  for (;;) {
    const std::optional<size_t> limit = ReadCgroupNumber(folder / limitName);
    if (limit && *limit < kUnlimited) {
      const size_t usage = ReadCgroupNumber(folder / usageName).value_or(0);
      const size_t left = *limit > usage ? *limit - usage : 0;
      headroom = headroom == 0 ? std::max<size_t>(left, 1) : std::min(headroom, std::max<size_t>(left, 1));
    }
    if (folder == root || !folder.has_parent_path() || folder.parent_path() == folder) break;
    folder = folder.parent_path();
  }
  return headroom;
}

}  // namespace

size_t AvailableMemoryBytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  size_t kib = 0;
  std::string unit;
  while (meminfo >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  return 0;
}

size_t CgroupHeadroomBytes() {
  // /proc/self/cgroup: "0::/path" (v2) or "N:memory:/path" (v1, possibly "N:cpu,memory:/path").
  std::ifstream cgroups("/proc/self/cgroup");
  std::string line;
  size_t headroom = 0;
  const auto tighter = [&](size_t h) {
    if (h > 0) headroom = headroom == 0 ? h : std::min(headroom, h);
  };
  while (std::getline(cgroups, line)) {
    const size_t first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1);
    const std::string path = line.substr(second + 1);
    if (controllers.empty()) {
      const std::filesystem::path root = "/sys/fs/cgroup";
      tighter(HeadroomUpTo(root / path.substr(path.empty() ? 0 : 1), root, "memory.max", "memory.current"));
    } else if (("," + controllers + ",").find(",memory,") != std::string::npos) {
      const std::filesystem::path root = "/sys/fs/cgroup/memory";
      tighter(HeadroomUpTo(root / path.substr(path.empty() ? 0 : 1), root, "memory.limit_in_bytes",
                           "memory.usage_in_bytes"));
    }
  }
  return headroom;
}

MemoryBudget DefaultMemoryBudget() {
  const size_t available = AvailableMemoryBytes(), cgroup = CgroupHeadroomBytes();
  if (cgroup > 0 && (available == 0 || cgroup < available)) return {cgroup, "the memory its cgroup allows"};
  return {available, "the memory this machine has available"};
}

size_t ResidentBytes() { return StatmBytes(1); }

size_t ResidentFileBytes() { return StatmBytes(2); }

size_t PeakResidentBytes() {
  rusage usage{};
  if (::getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return size_t(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

std::string FormatBytes(size_t bytes) {
  char text[32];
  const double value = double(bytes);
  constexpr double kKiB = 1024.0, kMiB = kKiB * 1024.0, kGiB = kMiB * 1024.0, kTiB = kGiB * 1024.0;
  if (value >= kTiB)
    std::snprintf(text, sizeof(text), "%.1f TiB", value / kTiB);
  else if (value >= kGiB)
    std::snprintf(text, sizeof(text), "%.1f GiB", value / kGiB);
  else if (value >= kMiB)
    std::snprintf(text, sizeof(text), "%.0f MiB", value / kMiB);
  else
    std::snprintf(text, sizeof(text), "%.0f KiB", value / kKiB);
  return text;
}

size_t ParseByteCount(const std::string& text, const std::string& option) {
  const auto fail = [&]() -> size_t {
    throw InputError(option + ": must be a size like 512M, 1.5G, 2GiB or 800MB, got '" + text + "'");
  };
  size_t digits = 0;
  bool point = false;
  while (digits < text.size() && (std::isdigit(static_cast<unsigned char>(text[digits])) ||
                                  (text[digits] == '.' && !point))) {
    point = point || text[digits] == '.';
    ++digits;
  }
  if (digits == 0 || digits > 20) return fail();
  const std::string unit = text.substr(digits);
  struct Unit {
    const char* name;
    double scale;
  };
  constexpr double kKi = 1024.0;
  constexpr double kMi = kKi * kKi, kGi = kMi * kKi, kTi = kGi * kKi;
  static const Unit kUnits[] = {{"", 1.0},   {"B", 1.0},    {"k", kKi},   {"K", kKi},   {"KiB", kKi}, {"kB", 1e3},
                                {"m", kMi},  {"M", kMi},    {"MiB", kMi}, {"MB", 1e6},  {"g", kGi},   {"G", kGi},
                                {"GiB", kGi}, {"GB", 1e9},  {"t", kTi},   {"T", kTi},   {"TiB", kTi}, {"TB", 1e12}};
  const Unit* found = nullptr;
  for (const Unit& u : kUnits)
    if (unit == u.name) found = &u;
  if (found == nullptr) return fail();
  std::istringstream number(text.substr(0, digits));
  number.imbue(std::locale::classic());
  double value = 0.0;
  if (!(number >> value)) return fail();
  const double bytes = std::floor(value * found->scale);
  if (!(bytes >= 1.0) || bytes > double(std::numeric_limits<size_t>::max() / 2)) return fail();
  return size_t(bytes);
}

void ReturnFreedMemory() { malloc_trim(0); }

}  // namespace ssgi
