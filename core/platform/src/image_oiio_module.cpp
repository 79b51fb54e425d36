// The OpenImageIO side of image_io.cpp, built as a module that image_io.cpp loads on first use.
// Debian's OpenImageIO pulls in about 300 shared libraries (OpenCV, FFmpeg, GDAL, ...) whose loading
// and static constructors cost a process about half a second of CPU; linked into rayspace, every
// run paid it, the ones that write no image included. The interface is plain C: no exception and no
// C++ object crosses the module boundary.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#include "image_oiio_module.h"

namespace {

void Report(char* error, std::size_t capacity, const std::string& text) {
  if (capacity > 0) std::snprintf(error, capacity, "%s", text.c_str());
}

}  // namespace

extern "C" {

int rayspace_oiio_can_write(const char* path, char* error, std::size_t capacity) {
  if (OIIO::ImageOutput::create(path)) return 1;
  Report(error, capacity, OIIO::geterror());
  return 0;
}

int rayspace_oiio_write(const char* name, const char* temp_path, int width, int height, const unsigned char* rgb,
                        RayspaceImageSink sink, void* sink_context, int* in_memory, char* error,
                        std::size_t capacity) {
  *in_memory = 0;
  // The format follows the name the user gave, not the temporary file's.
  auto image = OIIO::ImageOutput::create(name);
  if (!image) {
    Report(error, capacity, "cannot write an image in this format (" + OIIO::geterror() + ")");
    return 0;
  }
  const OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  const bool to_memory = image->supports("ioproxy") && image->set_ioproxy(&memory);
  if (!image->open(temp_path, spec) || !image->write_image(OIIO::TypeDesc::UINT8, rgb) || !image->close()) {
    Report(error, capacity, "cannot write image: " + image->geterror());
    return 0;
  }
  if (to_memory) {
    sink(sink_context, bytes.data(), bytes.size());
    *in_memory = 1;
  }
  return 1;
}

}  // extern "C"
