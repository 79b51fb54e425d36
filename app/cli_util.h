// Helpers shared by the CLI's subcommands.
#pragma once
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "rayspace/error.h"
#include "rayspace/scene.h"

namespace rayspace::app {

// Parses --size WxH (or one size of another option); each side in [1, kMaxImageSide]. Throws
// InputError naming the option.
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

// Fails, naming `what`, on an output file that cannot be written, before time is spent on it; leaves
// no file behind when there was none.
inline void ProbeWritable(const std::string& path, const char* what) {
  const bool existed = std::filesystem::exists(path);
  std::ofstream probe(path, std::ios::app);
  if (!probe) ThrowInput("{}: cannot write {}", path, what);
  probe.close();
  if (!existed) std::filesystem::remove(path);
}

// Loads the scene and sets the frame size from the scene or --size.
inline Scene LoadSceneForFrame(const std::string& path, const std::string& data, const std::string& size, int& width,
                               int& height) {
  LoadOptions lo;
  lo.data_root = data;
  Scene scene = LoadScene(path, lo);
  width = scene.width;
  height = scene.height;
  if (!size.empty()) ParseSize(size, width, height);
  return scene;
}

}  // namespace rayspace::app
