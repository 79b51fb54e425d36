#include "png_writer.h"

#include <png.h>

#include <algorithm>
#include <cctype>

namespace rayspace {

bool IsPngPath(const std::string& path) {
  const std::size_t dot = path.find_last_of("./");
  if (dot == std::string::npos || path[dot] != '.') return false;
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == "png";
}

std::string EncodePng(int width, int height, const std::vector<std::uint8_t>& rgb, std::string& error) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  image.format = PNG_FORMAT_RGB;
  // libpng's simplified API: the first call sizes the encoding, the second writes it.
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&image, nullptr, &size, 0, rgb.data(), 0, nullptr)) {
    error = image.message;
    png_image_free(&image);
    return {};
  }
  std::string bytes(size, '\0');
  if (!png_image_write_to_memory(&image, bytes.data(), &size, 0, rgb.data(), 0, nullptr)) {
    error = image.message;
    png_image_free(&image);
    return {};
  }
  bytes.resize(size);
  return bytes;
}

}  // namespace rayspace
