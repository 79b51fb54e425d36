#include "rayspace/shard.h"

#include <regex>

#include "rayspace/error.h"

namespace rayspace {

Shard ParseShard(const std::string& text) {
  static const std::regex re(R"((\d{1,6})/(\d{1,6}))");
  std::smatch m;
  if (!std::regex_match(text, m, re)) ThrowInput("--shard '{}': expected I/N, e.g. 0/4", text);
  const Shard s{std::stoi(m[1]), std::stoi(m[2])};
  if (s.count < 1 || s.index >= s.count) ThrowInput("--shard '{}': needs 0 <= I < N", text);
  return s;
}

}  // namespace rayspace
