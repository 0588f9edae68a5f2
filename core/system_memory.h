// The machine's and the process's memory, as a command judges what it may allocate: what the system
// could give the process now, the cgroup's limit, the process's resident set and byte counts as a
// command line writes them.
#pragma once

#include <cstddef>
#include <string>

namespace ssgi {

// What a command may allocate beyond what the process holds now, and where that figure comes from.
struct MemoryBudget {
  size_t bytes = 0;  // 0: unknown, nothing is refused
  // What the figure is, for messages: "the memory this machine has available", "--max-memory 8.0 GiB".
  std::string source;
  // The figure covers what the process holds already (a --max-memory limit on the whole process),
  // rather than what it may add (the memory available).
  bool coversProcess = false;
};

// The memory the system could give this process now (MemAvailable of /proc/meminfo), or 0 where
// that is unknown.
size_t AvailableMemoryBytes();
// What the process's memory cgroup lets it grow by: its limit less its usage, over the cgroup and
// its ancestors (cgroup v2 memory.max and memory.current, or v1 memory.limit_in_bytes and
// memory.usage_in_bytes); 0 where there is no limit or it is unknown.
size_t CgroupHeadroomBytes();
// The default budget: the smaller of the memory available and the cgroup's headroom.
MemoryBudget DefaultMemoryBudget();

// The process's resident set now and at its peak so far (Linux), in bytes; 0 where unknown.
size_t ResidentBytes();
// Gives the heap's free pages back to the system (glibc's malloc_trim, every arena): after a
// one-time build whose temporaries, freed on worker threads, would otherwise stay resident in
// those threads' arenas through the rest of the frame.
void ReturnFreedMemory();
size_t PeakResidentBytes();
// The file-backed part of the resident set now (RssFile + RssShmem): mostly the shared libraries'
// code and read-only data, clean pages the kernel can drop and read again under memory pressure,
// unlike the anonymous rest (heap, stacks, relocated data). 0 where unknown.
size_t ResidentFileBytes();

// "1.5 GiB", "730 MiB", "12 KiB": for messages.
std::string FormatBytes(size_t bytes);
// A byte count as a command line gives it: a number (a fraction allowed, "1.5G") with an optional
// unit. k, m, g, t (either case) and KiB, MiB, GiB, TiB are powers of 1024; kB, MB, GB, TB powers
// of 1000; B or no unit is bytes. Throws InputError naming `option` for anything else, or a count below one.
size_t ParseByteCount(const std::string& text, const std::string& option = "--max-memory");

}  // namespace ssgi
