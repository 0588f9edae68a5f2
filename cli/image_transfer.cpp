#include "cli/image_transfer.h"

#include <lz4.h>
#include <turbojpeg.h>

#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>

#include "core/check.h"
#include "core/stopwatch.h"

namespace ssgi::cli {
namespace {

constexpr uint32_t kMagic = 0x53564931;  // "SVI1"

// Ranks of one run are the same program on the same kind of machine: the header is copied as it is
// laid out in memory.
struct Header {
  uint32_t magic = kMagic;
  int32_t index = -1;
  int32_t width = 0, height = 0;
  uint8_t kind = 0, encoding = 0;
  uint8_t padding[2] = {0, 0};
  uint32_t errorBytes = 0;
  uint64_t rawBytes = 0;      // the pixels' bytes before encoding
  uint64_t encodedBytes = 0;  // after the header and the error text
  double renderMs = 0.0;
  double encodeMs = 0.0;  // on the rank that sent it
};

// One libjpeg-turbo handle per thread: a handle is not to be shared between threads.
struct TurboJpeg {
  explicit TurboJpeg(bool compress) : handle(compress ? tjInitCompress() : tjInitDecompress()) {
    if (!handle) throw std::runtime_error(std::string("libjpeg-turbo: ") + tjGetErrorStr2(nullptr));
  }
  ~TurboJpeg() { tjDestroy(handle); }
  TurboJpeg(const TurboJpeg&) = delete;
  TurboJpeg& operator=(const TurboJpeg&) = delete;
  tjhandle handle;
};

tjhandle Compressor() {
  thread_local TurboJpeg compressor(true);
  return compressor.handle;
}

tjhandle Decompressor() {
  thread_local TurboJpeg decompressor(false);
  return decompressor.handle;
}

const uint8_t* PixelData(const ViewImage& image) {
  return image.kind == ImageFileKind::kPng ? image.rgb8.data() : reinterpret_cast<const uint8_t*>(image.rgb32.data());
}

}  // namespace

const char* TransferEncodingName(TransferEncoding encoding) {
  switch (encoding) {
    case TransferEncoding::kRaw:
      return "raw";
    case TransferEncoding::kLz4:
      return "lz4";
    case TransferEncoding::kJpeg:
      return "jpeg";
  }
  return "?";
}

TransferTimes EncodeViewImage(const ViewImage& image, TransferEncoding encoding, int jpegQuality,
                              std::vector<uint8_t>& message) {
  Stopwatch clock;
  Header header;
  header.index = image.index;
  header.width = image.width;
  header.height = image.height;
  header.kind = uint8_t(image.kind);
  header.encoding = uint8_t(encoding);
  header.errorBytes = uint32_t(image.error.size());
  header.renderMs = image.renderMs;
  const bool failed = !image.error.empty();
  header.rawBytes = failed ? 0 : image.PixelBytes();
  const size_t start = sizeof(Header) + image.error.size();
  const uint8_t* pixels = PixelData(image);
  size_t encoded = 0;
  if (!failed) {
    switch (encoding) {
      case TransferEncoding::kRaw:
        message.resize(start + header.rawBytes);
        std::memcpy(message.data() + start, pixels, header.rawBytes);
        encoded = header.rawBytes;
        break;
      case TransferEncoding::kLz4: {
        SSGI_CHECK_LE(header.rawBytes, size_t(LZ4_MAX_INPUT_SIZE));
        const int bound = LZ4_compressBound(int(header.rawBytes));
        message.resize(start + size_t(bound));
        const int written =
            LZ4_compress_default(reinterpret_cast<const char*>(pixels), reinterpret_cast<char*>(message.data() + start),
                                 int(header.rawBytes), bound);
        SSGI_CHECK_GT(written, 0);
        encoded = size_t(written);
        break;
      }
      case TransferEncoding::kJpeg: {
        SSGI_CHECK(image.kind == ImageFileKind::kPng);
        unsigned long bound = tjBufSize(image.width, image.height, TJSAMP_420);
        message.resize(start + bound);
        unsigned char* out = message.data() + start;
        unsigned long size = bound;
        if (tjCompress2(Compressor(), image.rgb8.data(), image.width, 0, image.height, TJPF_RGB, &out, &size,
                        TJSAMP_420, jpegQuality, TJFLAG_NOREALLOC) != 0)
          throw std::runtime_error(std::string("libjpeg-turbo: ") + tjGetErrorStr2(Compressor()));
        encoded = size;
        break;
      }
    }
  } else {
    message.resize(start);
  }
  header.encodedBytes = encoded;
  message.resize(start + encoded);
  header.encodeMs = clock.Milliseconds();
  std::memcpy(message.data(), &header, sizeof(Header));
  std::memcpy(message.data() + sizeof(Header), image.error.data(), image.error.size());
  TransferTimes times;
  times.rawBytes = header.rawBytes;
  times.encodedBytes = encoded;
  times.encodeMs = header.encodeMs;
  return times;
}

void DecodeViewImage(const std::vector<uint8_t>& message, ViewImage& image, TransferTimes& times) {
  Stopwatch clock;
  Header header;
  if (message.size() < sizeof(Header)) throw std::runtime_error("a view's message is shorter than its header");
  std::memcpy(&header, message.data(), sizeof(Header));
  if (header.magic != kMagic || sizeof(Header) + header.errorBytes + header.encodedBytes != message.size() ||
      header.kind > uint8_t(ImageFileKind::kExr) || header.encoding > uint8_t(TransferEncoding::kJpeg))
    throw std::runtime_error("a view's message is malformed (ranks of different builds?)");
  image.index = header.index;
  image.width = header.width;
  image.height = header.height;
  image.kind = ImageFileKind(header.kind);
  image.renderMs = header.renderMs;
  image.error.assign(reinterpret_cast<const char*>(message.data() + sizeof(Header)), header.errorBytes);
  times.rawBytes = header.rawBytes;
  times.encodedBytes = header.encodedBytes;
  times.encodeMs = header.encodeMs;
  if (!image.error.empty()) {
    image.rgb8.clear();
    image.rgb32.clear();
    times.decodeMs = clock.Lap();
    return;
  }
  const size_t pixelCount = size_t(image.width) * size_t(image.height) * 3;
  uint8_t* out = nullptr;
  if (image.kind == ImageFileKind::kPng) {
    image.rgb8.resize(pixelCount);
    out = image.rgb8.data();
  } else {
    image.rgb32.resize(pixelCount);
    out = reinterpret_cast<uint8_t*>(image.rgb32.data());
  }
  if (image.PixelBytes() != header.rawBytes) throw std::runtime_error("a view's message has the wrong pixel count");
  const uint8_t* in = message.data() + sizeof(Header) + header.errorBytes;
  switch (TransferEncoding(header.encoding)) {
    case TransferEncoding::kRaw:
      if (header.encodedBytes != header.rawBytes) throw std::runtime_error("a raw view's message has the wrong size");
      std::memcpy(out, in, header.rawBytes);
      break;
    case TransferEncoding::kLz4: {
      const int got = LZ4_decompress_safe(reinterpret_cast<const char*>(in), reinterpret_cast<char*>(out),
                                          int(header.encodedBytes), int(header.rawBytes));
      if (got != int(header.rawBytes)) throw std::runtime_error("a view's LZ4 data is corrupt");
      break;
    }
    case TransferEncoding::kJpeg:
      if (image.kind != ImageFileKind::kPng) throw std::runtime_error("a JPEG message holds a float image");
      if (tjDecompress2(Decompressor(), in, static_cast<unsigned long>(header.encodedBytes), out, image.width, 0,
                        image.height, TJPF_RGB, 0) != 0)
        throw std::runtime_error(std::string("libjpeg-turbo: ") + tjGetErrorStr2(Decompressor()));
      break;
  }
  times.decodeMs = clock.Lap();
}

}  // namespace ssgi::cli
