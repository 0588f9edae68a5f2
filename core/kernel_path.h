// Which definition of a pass's per-row kernel its driver runs (docs/design.md §11-§12): the Highway twin,
// dispatched to the best target of the machine (what frames use), or the scalar definition the twin
// must equal bit for bit (for the tests that check it and the benchmarks that measure the gain).
#pragma once

namespace ssgi {

enum class KernelPath { kSimd, kScalar };

}  // namespace ssgi
