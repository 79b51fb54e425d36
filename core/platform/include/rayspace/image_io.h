#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "rayspace/output_file.h"

namespace rayspace {

// Throws InputError naming `path` unless OpenImageIO writes the image format its extension names
// (an image output is checked before the frame that fills it).
void CheckImageFormat(const std::string& path);

// Writes 8-bit RGB pixels (row-major, top row first) with OpenImageIO to `out` (OutputFile::Write; the
// caller publishes it), in the format its extension names: encoded in memory and written whole, or,
// for a format OpenImageIO cannot encode to memory, through the temporary file's name. Throws
// InputError naming the file.
void WriteImage(OutputFile& out, int width, int height, const std::vector<std::uint8_t>& rgb);

}  // namespace rayspace
