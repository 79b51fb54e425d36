// Reading the files a user names (scenes, meshes, material files, saved pass inputs, kernels).
//
// Every such file is opened once and checked after opening, so what is read is what was checked:
// anything but a regular file (a directory, a FIFO, a device, a socket) is refused, because
// reading a FIFO blocks forever and a device such as /dev/zero never ends. What is read is bounded,
// so no file, however large or however it grows, exhausts memory. Every failure is an InputError
// whose one-line message names the file.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace rayspace {

// Bounds on what one file may hold: text inputs (scene JSON, MTL, a saved call's pass.json and
// comparison.json, kernel SPIR-V) and bulk data (meshes, saved buffers). A mesh of the largest scene
// rayspace takes (2^28 triangles) needs about 3.5 GiB as binary PLY.
inline constexpr std::uint64_t kMaxTextFileBytes = std::uint64_t{256} << 20;
inline constexpr std::uint64_t kMaxDataFileBytes = std::uint64_t{4} << 30;

enum class Gzip { kNo, kByExtension };

struct InputFile {
  std::string_view what;           // the file's role in messages: "scene file", "mesh", "material file"
  std::uint64_t max_bytes = kMaxTextFileBytes;  // decompressed, for gzip (and compressed too)
  Gzip gzip = Gzip::kNo;  // kByExtension: a name ending in ".gz" is gzip data, decompressed while read
  bool text = false;      // a text format (OBJ, MTL): gzip data holding a NUL byte is refused where it is met
};

// The whole file, decompressed when asked. Throws InputError naming the file when it cannot be
// opened, is not a regular file, holds (or decompresses to) more than spec.max_bytes, or is not
// valid gzip data: corrupt, truncated or empty.
std::string ReadInputFile(const std::filesystem::path& path, const InputFile& spec);

// "" when `path` is a regular file (symbolic links followed); otherwise why it is not one, as the
// end of a sentence: "does not exist", "is a directory", "is a FIFO (named pipe)", ... For files
// handed to another program (glslc) that rayspace does not read itself.
std::string NotRegularFile(const std::filesystem::path& path);

// True when the name ends in ".gz" (case-insensitive).
bool IsGzipName(const std::filesystem::path& path);

// The name without ".gz" and then without its extension: "conference.obj.gz" -> "conference".
std::string StemWithoutGz(const std::filesystem::path& path);

}  // namespace rayspace
