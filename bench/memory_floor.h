// The memory floor of a streaming pass (docs/design.md §13: "streaming passes within 2x of a memory
// copy of the same bytes"): a benchmark that reads and writes, per pixel, as many bytes as the pass
// does, with the pass's split into row bands, so that the pass's time is quoted as a ratio to it,
// both measured in the same binary and run. bench/README.md lists the floors registered.
#pragma once

#include <cstddef>

namespace ssgi {

// Registers BM_MemoryFloor/read:R/write:W/size:S/threads:T for S in {1024, 2048} (an S x S image)
// and T in {1, 2} (ssgi::ThreadLimit): per pixel, R bytes read from one plane and W bytes written to
// another, by bands of rows (ssgi::ParallelForRowBands), both planes made once and reused. Reports
// pixels (items) and bytes read plus written per second. A floor registered already is not
// registered again, so passes that move the same bytes share theirs.
void RegisterMemoryFloor(size_t readBytesPerPixel, size_t writeBytesPerPixel);

}  // namespace ssgi
