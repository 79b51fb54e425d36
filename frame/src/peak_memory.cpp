#include "rayspace/frame/peak_memory.h"

#include <fstream>
#include <string>

#include <malloc.h>
#include <sys/resource.h>

namespace rayspace::app {
namespace {

// A "Key:   1234 kB" line of /proc/self/status in bytes; 0 when absent.
std::size_t StatusBytes(const char* key) {
  std::ifstream f("/proc/self/status");
  const std::string prefix = std::string(key) + ":";
  std::string line;
  while (std::getline(f, line))
    if (line.rfind(prefix, 0) == 0) return std::stoull(line.substr(prefix.size())) * 1024;
  return 0;
}

}  // namespace

bool ResetPeakRss() {
#ifdef __GLIBC__
  malloc_trim(0);  // what the previous part freed should not count towards the next part's peak
#endif
  std::ofstream f("/proc/self/clear_refs");
  f << "5";
  f.flush();
  return static_cast<bool>(f);
}

std::size_t PeakRssBytes() {
  if (const std::size_t hwm = StatusBytes("VmHWM")) return hwm;
  rusage u{};
  if (getrusage(RUSAGE_SELF, &u) != 0) return 0;
  return static_cast<std::size_t>(u.ru_maxrss) * 1024;  // kilobytes on Linux
}

std::size_t CurrentRssBytes() { return StatusBytes("VmRSS"); }

}  // namespace rayspace::app
