#include "rayspace/frame/version.h"

#include <CGAL/version.h>
#include <CLI/Version.hpp>
#include <OpenImageIO/oiioversion.h>
#include <png.h>
#include <embree3/rtcore_config.h>
#include <fmt/format.h>
#include <glm/detail/setup.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>
#ifdef RAYSPACE_HAVE_VULKAN
#include <vulkan/vulkan_core.h>
#endif

#include "rayspace_version.h"

namespace rayspace::app {
namespace {
std::vector<std::string>& Arguments() {
  static std::vector<std::string> args;
  return args;
}
}  // namespace

void SetArguments(int argc, char** argv) { Arguments().assign(argv, argv + argc); }

void AddVersion(nlohmann::json& j) {
  j["rayspace_version"] = RAYSPACE_VERSION;
  j["commit"] = RAYSPACE_COMMIT;
}

void AddProvenance(nlohmann::json& j) {
  AddVersion(j);
  j["arguments"] = Arguments();
}

std::string VersionText() {
  std::string s = fmt::format("rayspace {}\ncommit {}\n", RAYSPACE_VERSION, RAYSPACE_COMMIT);
#ifdef RAYSPACE_HAVE_VULKAN
  s += fmt::format("backends: emu, vulkan (Vulkan headers 1.{}.{})\n", VK_API_VERSION_MINOR(VK_HEADER_VERSION_COMPLETE),
                   VK_HEADER_VERSION);
#else
  s += "backends: emu (built without Vulkan)\n";
#endif
  s += fmt::format("compiler: {} {}, -ffp-contract=off{}\n",
#ifdef __clang__
                   "clang",
#else
                   "GCC",
#endif
                   __VERSION__,
#ifdef NDEBUG
                   ""
#else
                   ", debug checks"
#endif
  );
  s += fmt::format("libraries: Embree {}, CGAL {}, OpenImageIO {}, libpng {}, OpenMP {}, GLM {}.{}.{}, fmt {}.{}.{}, CLI11 {}, nlohmann-json {}.{}.{}\n",
                   RTC_VERSION_STRING, CGAL_VERSION_STR, OIIO_VERSION_STRING, PNG_LIBPNG_VER_STRING, _OPENMP, GLM_VERSION_MAJOR, GLM_VERSION_MINOR,
                   GLM_VERSION_PATCH, FMT_VERSION / 10000, FMT_VERSION / 100 % 100, FMT_VERSION % 100, CLI11_VERSION,
                   NLOHMANN_JSON_VERSION_MAJOR, NLOHMANN_JSON_VERSION_MINOR, NLOHMANN_JSON_VERSION_PATCH);
  return s;
}

std::string BuildCommit() { return RAYSPACE_COMMIT; }

}  // namespace rayspace::app
