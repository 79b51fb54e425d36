#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "rayspace/output_file.h"

namespace rayspace {

// Throws InputError naming `path` unless its extension names a format rayspace writes: PNG (libpng,
// in the process) or any OpenImageIO writes (the image module, loaded on first use). An image output
// is checked before the frame that fills it.
void CheckImageFormat(const std::string& path);

// Writes 8-bit RGB pixels (row-major, top row first) to `out` (OutputFile::Write; the caller publishes
// it) in the format its extension names: PNG with libpng; any other with OpenImageIO, encoded in
// memory and written whole, or, for a format OpenImageIO cannot encode to memory, through the
// temporary file's name. Throws InputError naming the file.
void WriteImage(OutputFile& out, int width, int height, const std::vector<std::uint8_t>& rgb);

}  // namespace rayspace
