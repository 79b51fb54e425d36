// PNG, the default image format, encoded with libpng in the process: loading the OpenImageIO module
// (image_oiio_module.cpp) costs a process about 0.4 s of CPU, more than a small frame's whole render.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace rayspace {

// Whether `path` names a PNG file (its extension is .png, in any case).
bool IsPngPath(const std::string& path);

// 8-bit RGB pixels (row-major, top row first) as the bytes of a PNG file, or "" with `error` set.
// The same pixels always give the same bytes.
std::string EncodePng(int width, int height, const std::vector<std::uint8_t>& rgb, std::string& error);

}  // namespace rayspace
