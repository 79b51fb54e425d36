// Image files: PNG written in the process with libpng. A known-answer test decodes the file with
// libpng's reader and compares every pixel; the same pixels give the same bytes.
#include <png.h>

#include <filesystem>
#include <vector>

#include <doctest/doctest.h>

#include "rayspace/error.h"
#include "rayspace/image_io.h"
#include "rayspace/output_file.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

void Write(const fs::path& p, int w, int h, const std::vector<std::uint8_t>& rgb) {
  rayspace::CheckImageFormat(p.string());
  rayspace::OutputOptions options;
  options.what = "the image";
  rayspace::OutputFile out(p.string(), options);
  rayspace::WriteImage(out, w, h, rgb);
  out.Publish();
}

// The file's pixels as 8-bit RGB, decoded by libpng; empty when it is not a PNG of that size.
std::vector<std::uint8_t> Decode(const std::string& bytes, int w, int h) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size())) return {};
  if (image.width != static_cast<png_uint_32>(w) || image.height != static_cast<png_uint_32>(h)) {
    png_image_free(&image);
    return {};
  }
  image.format = PNG_FORMAT_RGB;
  std::vector<std::uint8_t> rgb(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, rgb.data(), 0, nullptr)) return {};
  return rgb;
}

}  // namespace

TEST_CASE("image files: a PNG holds exactly the pixels written, and the same pixels give the same bytes") {
  const rayspace::test::TempDir tmp;
  const fs::path& dir = tmp.path();
  const int w = 5, h = 3;  // odd sizes: no row padding hides a stride error
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<std::uint8_t>(i * 37 + 11);
  Write(dir / "a.png", w, h, rgb);
  Write(dir / "b.PNG", w, h, rgb);  // the extension in any case
  const std::string a = tmp.Read("a.png");
  REQUIRE(a.size() > 8);
  CHECK(a.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
  CHECK(Decode(a, w, h) == rgb);
  CHECK(tmp.Read("b.PNG") == a);
  // A pixel changed is a pixel decoded changed: the test can see a wrong image.
  rgb[7] ^= 1;
  Write(dir / "c.png", w, h, rgb);
  CHECK(Decode(tmp.Read("c.png"), w, h) == rgb);
  CHECK(tmp.Read("c.png") != a);
}

TEST_CASE("image files: a name without an image extension is refused, naming it") {
  CHECK_THROWS_WITH_AS(rayspace::CheckImageFormat("frame.notanimage"),
                       doctest::Contains("frame.notanimage: cannot write an image in this format"), rayspace::InputError);
}
