#pragma once
#include <cstdint>
#include <filesystem>
#include <vector>

namespace rayspace {

// Writes 8-bit RGB pixels (row-major, top row first) with OpenImageIO; the format follows the
// extension. Throws InputError naming the file when it cannot be written.
void WriteImage(const std::filesystem::path& path, int width, int height, const std::vector<std::uint8_t>& rgb);

}  // namespace rayspace
