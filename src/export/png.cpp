#include "export/png.h"

#include <png.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include "core/error.h"
#include "io/write_mesh.h"

namespace s2p {
namespace {

constexpr long long kMaxPixels = 1LL << 28;  // refuse absurd sizes rather than exhaust memory

png_image emptyPngImage() {
  png_image image;
  std::memset(&image, 0, sizeof(image));
  image.version = PNG_IMAGE_VERSION;
  return image;
}

}  // namespace

void writePng(const std::filesystem::path& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      static_cast<long long>(image.width) * image.height > kMaxPixels)
    throw InputError("writePng " + path.string() + ": invalid image size " +
                     std::to_string(image.width) + "x" + std::to_string(image.height));
  if (image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3)
    throw InputError("writePng " + path.string() + ": the pixel buffer has " +
                     std::to_string(image.rgb.size()) + " bytes, expected width·height·3 = " +
                     std::to_string(static_cast<std::size_t>(image.width) * image.height * 3));

  png_image png = emptyPngImage();
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  // One pass into a buffer of the largest size the image can take: asking libpng for the size
  // first encodes the image twice. (PNG_IMAGE_FLAG_FAST would make the files 40–60 % larger.)
  png_alloc_size_t bytes = PNG_IMAGE_PNG_SIZE_MAX(png);
  std::string encoded(bytes, '\0');
  if (!png_image_write_to_memory(&png, encoded.data(), &bytes, 0, image.rgb.data(), 0, nullptr))
    throw IoError("writePng " + path.string() + ": libpng cannot encode the image: " + png.message);
  encoded.resize(bytes);

  writeFileAtomically(path, encoded);
}

Image readPng(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("readPng: cannot open " + path.string() + ": check the path");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw IoError("readPng: cannot read " + path.string());

  png_image png = emptyPngImage();
  if (!png_image_begin_read_from_memory(&png, bytes.data(), bytes.size())) {
    const std::string message = png.message;
    png_image_free(&png);
    throw FormatError("readPng " + path.string() + ": not a valid PNG file: " + message);
  }
  if (static_cast<long long>(png.width) * png.height > kMaxPixels) {
    png_image_free(&png);
    throw FormatError("readPng " + path.string() + ": image of " + std::to_string(png.width) + "x" +
                      std::to_string(png.height) + " pixels is too large");
  }
  png.format = PNG_FORMAT_RGB;
  Image image;
  image.width = static_cast<int>(png.width);
  image.height = static_cast<int>(png.height);
  image.rgb.resize(PNG_IMAGE_SIZE(png));
  const png_color white{255, 255, 255};
  if (!png_image_finish_read(&png, &white, image.rgb.data(), 0, nullptr)) {
    const std::string message = png.message;
    png_image_free(&png);
    throw FormatError("readPng " + path.string() + ": truncated or corrupt PNG: " + message);
  }
  return image;
}

}  // namespace s2p
