// The transfer encodings of render-views (cli/image_transfer.h): raw and LZ4 give back the exact
// pixels, JPEG close ones in fewer bytes, and a failed view travels as its message.
#include "cli/image_transfer.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>

namespace ssgi::cli {
namespace {

ViewImage Gradient(int width, int height) {
  ViewImage image;
  image.index = 7;
  image.width = width;
  image.height = height;
  image.renderMs = 12.5;
  image.rgb8.resize(size_t(width) * size_t(height) * 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        image.rgb8[(size_t(y) * size_t(width) + size_t(x)) * 3 + size_t(c)] = uint8_t((x * (c + 1) + y * 2) & 255);
  return image;
}

TEST_CASE("image transfer: raw and lz4 give back the exact pixels, jpeg close ones", "[cli][views]") {
  const ViewImage image = Gradient(67, 45);
  for (TransferEncoding encoding : {TransferEncoding::kRaw, TransferEncoding::kLz4, TransferEncoding::kJpeg}) {
    CAPTURE(TransferEncodingName(encoding));
    std::vector<uint8_t> message;
    const TransferTimes sent = EncodeViewImage(image, encoding, 90, message);
    CHECK(sent.rawBytes == image.rgb8.size());
    ViewImage back;
    TransferTimes received;
    DecodeViewImage(message, back, received);
    CHECK(received.encodedBytes == sent.encodedBytes);
    CHECK(back.index == 7);
    CHECK(back.width == 67);
    CHECK(back.height == 45);
    CHECK(back.renderMs == 12.5);
    REQUIRE(back.rgb8.size() == image.rgb8.size());
    if (encoding != TransferEncoding::kJpeg) {
      CHECK(back.rgb8 == image.rgb8);
    } else {
      double error = 0.0;
      for (size_t i = 0; i < image.rgb8.size(); ++i) error += std::abs(int(back.rgb8[i]) - int(image.rgb8[i]));
      CHECK(error / double(image.rgb8.size()) < 8.0);
    }
  }
  // Float images (EXR output) travel bit for bit.
  ViewImage exr;
  exr.index = 1;
  exr.width = 5;
  exr.height = 3;
  exr.kind = ImageFileKind::kExr;
  for (int i = 0; i < 45; ++i) exr.rgb32.push_back(std::ldexp(float(i) + 0.1f, i - 20));
  std::vector<uint8_t> message;
  EncodeViewImage(exr, TransferEncoding::kLz4, 90, message);
  ViewImage back;
  TransferTimes times;
  DecodeViewImage(message, back, times);
  CHECK(back.rgb32 == exr.rgb32);
  CHECK(back.kind == ImageFileKind::kExr);
}

TEST_CASE("image transfer: a failed view travels as its message, and a corrupt message is refused", "[cli][views]") {
  ViewImage failed;
  failed.index = 3;
  failed.error = "views.json:4: views[3].camera.target must differ from camera.position";
  std::vector<uint8_t> message;
  EncodeViewImage(failed, TransferEncoding::kLz4, 90, message);
  ViewImage back = Gradient(4, 4);
  TransferTimes times;
  DecodeViewImage(message, back, times);
  CHECK(back.index == 3);
  CHECK(back.error == failed.error);
  CHECK(back.rgb8.empty());
  message.pop_back();
  CHECK_THROWS(DecodeViewImage(message, back, times));
}

}  // namespace
}  // namespace ssgi::cli
