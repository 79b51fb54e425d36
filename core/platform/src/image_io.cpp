#include "rayspace/image_io.h"

#include <dlfcn.h>

#include <cstdlib>
#include <exception>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "image_oiio_module.h"
#include "png_writer.h"
#include "rayspace/error.h"

namespace rayspace {
namespace {

constexpr const char* kModuleName = "librayspace_image_oiio.so";

struct ImageModule {
  RayspaceOiioCanWrite can_write = nullptr;
  RayspaceOiioWrite write = nullptr;
};

// The places the module may be, in order: RAYSPACE_IMAGE_MODULE, the build tree this binary was
// built in, and lib/rayspace/ beside the binary's own bin/ (an installed layout).
std::vector<std::string> Candidates() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("RAYSPACE_IMAGE_MODULE"); env && *env) out.emplace_back(env);
#ifdef RAYSPACE_IMAGE_MODULE_BUILD_PATH
  out.emplace_back(RAYSPACE_IMAGE_MODULE_BUILD_PATH);
#endif
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) out.push_back((self.parent_path().parent_path() / "lib" / "rayspace" / kModuleName).string());
  return out;
}

const ImageModule& Module() {
  static ImageModule module;
  static std::once_flag once;
  std::call_once(once, [] {
    std::string tried;
    for (const auto& path : Candidates()) {
      void* handle = dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
      if (!handle) {
        tried += fmt::format("\n  {}: {}", path, dlerror());
        continue;
      }
      module.can_write = reinterpret_cast<RayspaceOiioCanWrite>(dlsym(handle, "rayspace_oiio_can_write"));
      module.write = reinterpret_cast<RayspaceOiioWrite>(dlsym(handle, "rayspace_oiio_write"));
      if (module.can_write && module.write) return;
      tried += fmt::format("\n  {}: not rayspace's image module (missing symbols)", path);
    }
    throw std::runtime_error(fmt::format(
        "cannot load {} (OpenImageIO, for image files); set RAYSPACE_IMAGE_MODULE to its path. Tried:{}",
        kModuleName, tried));
  });
  return module;
}

}  // namespace

void CheckImageFormat(const std::string& path) {
  if (IsPngPath(path)) return;
  char error[512] = {};
  if (!Module().can_write(path.c_str(), error, sizeof error))
    ThrowInput("{}: cannot write an image in this format ({}); name the file with an image extension such as .png",
               path, error);
}

void WriteImage(OutputFile& out, int width, int height, const std::vector<std::uint8_t>& rgb) {
  RS_CHECK(rgb.size() == static_cast<std::size_t>(width) * height * 3);
  if (IsPngPath(out.path())) {
    std::string why;
    const std::string png = EncodePng(width, height, rgb, why);
    if (png.empty()) ThrowInput("{}: cannot encode the PNG image: {}", out.path(), why);
    out.Write(png);
    return;
  }
  char error[512] = {};
  int in_memory = 0;
  // A failed write (a full disk) is an exception, which must not unwind through the module's frames.
  struct Sink {
    OutputFile* out;
    std::exception_ptr failure;
  } context{&out, nullptr};
  const auto sink = [](void* c, const void* data, std::size_t size) {
    auto& s = *static_cast<Sink*>(c);
    try {
      s.out->Write(std::string_view(static_cast<const char*>(data), size));
    } catch (...) {
      s.failure = std::current_exception();
    }
  };
  const bool ok = Module().write(out.path().c_str(), out.temp_path().string().c_str(), width, height, rgb.data(),
                                 sink, &context, &in_memory, error, sizeof error);
  if (context.failure) std::rethrow_exception(context.failure);
  if (!ok) ThrowInput("{}: {}", out.path(), error);
  if (!in_memory) out.Written();
}

}  // namespace rayspace
