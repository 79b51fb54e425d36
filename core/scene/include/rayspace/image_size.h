// An image size as the command line gives it: WxH, each side in [1, kMaxImageSide].
#pragma once
#include <regex>
#include <string>

#include "rayspace/error.h"
#include "rayspace/scene.h"

namespace rayspace {

// Parses WxH into w and h; throws InputError naming `option` (--size, or another option that takes a size).
inline void ParseSize(const std::string& s, int& w, int& h, const char* option = "--size") {
  static const std::regex re(R"((\d{1,9})x(\d{1,9}))");
  std::smatch m;
  if (!std::regex_match(s, m, re)) ThrowInput("{} '{}': expected WxH, e.g. 512x512", option, s);
  const long long lw = std::stoll(m[1]), lh = std::stoll(m[2]);
  if (lw < 1 || lh < 1 || lw > kMaxImageSide || lh > kMaxImageSide)
    ThrowInput("{} '{}': each side must be in [1, {}]", option, s, kMaxImageSide);
  w = static_cast<int>(lw);
  h = static_cast<int>(lh);
}

}  // namespace rayspace
