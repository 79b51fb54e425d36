#include "rayspace/error.h"

#include <cstdio>
#include <cstdlib>

namespace rayspace {

void CheckFailed(const char* expr, const char* file, int line, const std::string& msg) {
  std::fprintf(stderr, "rayspace: internal check failed: %s (%s:%d)%s%s\n", expr, file, line,
               msg.empty() ? "" : ": ", msg.c_str());
  std::abort();
}

}  // namespace rayspace
