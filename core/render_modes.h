// The small enumerations of how a frame is rendered, apart from the scene and the frame
// configuration (passes/frame/config.h), so buffers and passes that need one include only this.
#pragma once

namespace ssgi {

// How G-buffer word 1 stores the 24-bit view-space normal (core/gbuffer.h).
enum class NormalEncoding { kXyz8, kOct24 };

// "auto": run the effect when the scene calls for it (docs/design.md §9); on / off force it.
enum class EffectMode { kAuto, kOn, kOff };

// The display curve of the tonemap pass (passes/tonemap.h).
enum class Tonemap { kAces, kClamp };

// The anti-aliasing of the final image (passes/antialias.h): none, the analytic coverage of the
// geometric edges the rasterizer found (G-buffer edge coverage, GBAA style), or the coverage of the
// edges found in the image itself (morphological, passes/mlaa.h).
enum class Antialiasing { kOff, kEdge, kMlaa };

}  // namespace ssgi
