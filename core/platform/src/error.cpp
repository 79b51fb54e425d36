#include "rayspace/error.h"

#include <cstdio>
#include <cstdlib>

#include "rayspace/settings.h"

namespace rayspace {

void CheckFailed(const char* expr, const char* file, int line, const std::string& msg) {
  const std::string what = fmt::format("{} ({}:{}){}{}", expr, file, line, msg.empty() ? "" : ": ", msg);
  if (CurrentSettings().check_failures_throw) throw CheckFailure(what);
  std::fprintf(stderr, "rayspace: internal check failed: %s\n", what.c_str());
  std::abort();
}

}  // namespace rayspace
