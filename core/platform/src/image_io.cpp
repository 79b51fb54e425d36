#include "rayspace/image_io.h"

#include <OpenImageIO/imageio.h>

#include "rayspace/error.h"

namespace rayspace {

void WriteImage(const std::filesystem::path& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  RS_CHECK(rgb.size() == static_cast<std::size_t>(width) * height * 3);
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) ThrowInput("{}: cannot write image: {}", path.string(), OIIO::geterror());
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  if (!out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) || !out->close())
    ThrowInput("{}: cannot write image: {}", path.string(), out->geterror());
}

}  // namespace rayspace
