#include "rayspace/error.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace rayspace {
namespace {
std::atomic<bool> g_throw{false};
}  // namespace

void SetCheckFailuresThrow(bool on) { g_throw.store(on); }

void CheckFailed(const char* expr, const char* file, int line, const std::string& msg) {
  const std::string what = fmt::format("{} ({}:{}){}{}", expr, file, line, msg.empty() ? "" : ": ", msg);
  if (g_throw.load()) throw CheckFailure(what);
  std::fprintf(stderr, "rayspace: internal check failed: %s\n", what.c_str());
  std::abort();
}

}  // namespace rayspace
