#include "rayspace/image_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "rayspace/error.h"

namespace rayspace {

void CheckImageFormat(const std::string& path) {
  if (!OIIO::ImageOutput::create(path))
    ThrowInput("{}: cannot write an image in this format ({}); name the file with an image extension such as .png",
               path, OIIO::geterror());
}

void WriteImage(OutputFile& out, int width, int height, const std::vector<std::uint8_t>& rgb) {
  RS_CHECK(rgb.size() == static_cast<std::size_t>(width) * height * 3);
  // The format follows the name the user gave, not the temporary file's.
  auto image = OIIO::ImageOutput::create(out.path());
  if (!image) ThrowInput("{}: cannot write an image in this format ({})", out.path(), OIIO::geterror());
  const OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  const bool in_memory = image->supports("ioproxy") && image->set_ioproxy(&memory);
  if (!image->open(out.temp_path().string(), spec) || !image->write_image(OIIO::TypeDesc::UINT8, rgb.data()) ||
      !image->close())
    ThrowInput("{}: cannot write image: {}", out.path(), image->geterror());
  if (in_memory)
    out.Write(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  else
    out.Written();
}

}  // namespace rayspace
