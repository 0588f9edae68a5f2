// The images of `ssgi render-views` as they travel between processes (docs/user-guide.md
// "render-views"): a rendered view's pixels, and their transfer encodings, raw bytes, LZ4 (lossless)
// or JPEG (libjpeg-turbo, lossy, 8-bit images only), as image-transfer renderers send frames to
// their users.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/image_io.h"

namespace ssgi::cli {

// One view's image: 8-bit sRGB RGB for a PNG, linear float RGB for an EXR. A view that failed has no
// pixels and says why.
struct ViewImage {
  int index = -1;  // in the views file
  int width = 0, height = 0;
  ImageFileKind kind = ImageFileKind::kPng;
  std::vector<uint8_t> rgb8;  // kPng: interleaved R, G, B rows, top row first
  std::vector<float> rgb32;   // kExr: planar: the R rows, then the G rows, then the B rows
  std::string error;          // non-empty: the view did not render
  double renderMs = 0.0;

  size_t PixelBytes() const { return kind == ImageFileKind::kPng ? rgb8.size() : rgb32.size() * sizeof(float); }
};

enum class TransferEncoding { kRaw, kLz4, kJpeg };
// "raw", "lz4", "jpeg".
const char* TransferEncodingName(TransferEncoding encoding);

// What an encode or decode cost, for the run's report.
struct TransferTimes {
  size_t rawBytes = 0, encodedBytes = 0;
  double encodeMs = 0.0, decodeMs = 0.0;
};

// A view's image as one message: a fixed header (index, size, kind, encoding, the error's length,
// the render time) followed by the error text or the encoded pixels. jpegQuality (1-100) is used by
// kJpeg, which refuses EXR images (the caller checks that first). `message` is overwritten, its
// memory reused; returns the encode time and sizes.
TransferTimes EncodeViewImage(const ViewImage& image, TransferEncoding encoding, int jpegQuality,
                              std::vector<uint8_t>& message);
// The image a message holds, into `image` (its buffers reused). Throws std::runtime_error on a
// malformed message (a bug or a version mismatch between ranks). Sets `times`, the encode time as
// the sender measured it.
void DecodeViewImage(const std::vector<uint8_t>& message, ViewImage& image, TransferTimes& times);

}  // namespace ssgi::cli
