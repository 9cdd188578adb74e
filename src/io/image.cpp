#include "io/image.h"

#include <fmt/format.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <vector>

#include "core/error.h"

namespace s2p {

Image decodeImage(const std::uint8_t* data, std::size_t size, const std::string& what) {
  if (size == 0 || size > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw FormatError(fmt::format("{}: empty or oversized image ({} bytes)", what, size));
  int w = 0, h = 0, channels = 0;
  stbi_uc* pixels =
      stbi_load_from_memory(data, static_cast<int>(size), &w, &h, &channels, 3);  // force RGB
  if (pixels == nullptr || w <= 0 || h <= 0) {
    if (pixels) stbi_image_free(pixels);
    const char* reason = stbi_failure_reason();
    throw FormatError(fmt::format("{}: not a decodable image ({}); re-save it as PNG or JPG", what,
                                  reason ? reason : "unknown reason"));
  }
  Image image;
  image.width = w;
  image.height = h;
  image.rgb.assign(pixels, pixels + static_cast<std::size_t>(w) * h * 3);
  stbi_image_free(pixels);
  return image;
}

Image readImage(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(fmt::format("{}: cannot open the image file", path.string()));
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                std::istreambuf_iterator<char>());
  return decodeImage(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(),
                     path.string());
}

namespace {
void appendBytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                             static_cast<std::size_t>(size));
}
}  // namespace

std::string encodePng(const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3)
    throw IoError(fmt::format("cannot encode a {}×{} image with {} bytes as PNG", image.width,
                              image.height, image.rgb.size()));
  std::string out;
  if (!stbi_write_png_to_func(appendBytes, &out, image.width, image.height, 3, image.rgb.data(),
                              image.width * 3))
    throw IoError("PNG encoding failed");
  return out;
}

Eigen::Vector3d sampleBilinear(const Image& image, double u, double v) {
  if (image.width <= 0 || image.height <= 0 || !std::isfinite(u) || !std::isfinite(v))
    return Eigen::Vector3d::Zero();
  u -= std::floor(u);
  v -= std::floor(v);
  const double x = u * image.width - 0.5;
  const double y = (1.0 - v) * image.height - 0.5;  // row 0 is the top of the image
  const double fx = std::floor(x), fy = std::floor(y);
  const double tx = x - fx, ty = y - fy;
  auto wrap = [](long i, int n) { return static_cast<int>(((i % n) + n) % n); };
  const int x0 = wrap(static_cast<long>(fx), image.width),
            x1 = wrap(static_cast<long>(fx) + 1, image.width);
  const int y0 = wrap(static_cast<long>(fy), image.height),
            y1 = wrap(static_cast<long>(fy) + 1, image.height);
  auto px = [&](int xi, int yi) {
    const std::size_t o = (static_cast<std::size_t>(yi) * image.width + xi) * 3;
    return Eigen::Vector3d(image.rgb[o], image.rgb[o + 1], image.rgb[o + 2]);
  };
  const Eigen::Vector3d c = (1 - ty) * ((1 - tx) * px(x0, y0) + tx * px(x1, y0)) +
                            ty * ((1 - tx) * px(x0, y1) + tx * px(x1, y1));
  return c / 255.0;
}

}  // namespace s2p
