// Helpers shared by the CLI's subcommands.
#pragma once
#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>
#include <utility>

#include "rayspace/exit_codes.h"
#include "rayspace/error.h"
#include "rayspace/image_size.h"
#include "rayspace/output_file.h"
#include "rayspace/scene.h"

namespace rayspace::app {

// An output file the user named, checked now, before the work that fills it (OutputFile): it may not
// replace the scene or a mesh the run reads. "-" is standard output where `allow_stdout`.
inline OutputFile OpenOutput(const std::string& path, const char* what, const Scene* scene, bool allow_stdout = true) {
  if (path.empty()) return {};
  OutputOptions o;
  o.what = what;
  o.allow_stdout = allow_stdout;
  if (scene) o.inputs = scene->files;
  return OutputFile(path, std::move(o));
}

// Writes a command's outputs once its verdict is known. A failed write is bad input (exit 2), unless
// the run failed already: that exit code (an oracle mismatch, a divergence) must not be hidden, so the
// write's error is printed and the verdict returned.
template <typename Write>
ExitCode WriteOutputs(ExitCode verdict, Write&& write) {
  try {
    write();
  } catch (const InputError& e) {
    if (verdict == ExitCode::kOk) throw;
    std::fprintf(stderr, "rayspace: error: %s\n", e.what());
  }
  return verdict;
}

// Loads the scene and sets the frame size from the scene or --size, and its bounces from --bounces
// when given (>= 0).
inline Scene LoadSceneForFrame(const std::string& path, const std::string& data, const std::string& size, int& width,
                               int& height, int bounces = -1) {
  if (std::error_code ec; !data.empty() && !std::filesystem::is_directory(data, ec))
    ThrowInput("--data {}: not a directory (the data root, docs/data.md)", data);
  LoadOptions lo;
  lo.data_root = data;
  Scene scene = LoadScene(path, lo);
  if (bounces >= 0) scene.max_depth = bounces;
  width = scene.width;
  height = scene.height;
  if (!size.empty()) ParseSize(size, width, height);
  return scene;
}

// Where a frame's size came from, for messages about it: "--size", or the scene file's image.
inline std::string SizeFrom(const std::string& size, const Scene& scene) {
  return size.empty() ? scene.path.string() + ": the scene's image" : std::string("--size");
}

}  // namespace rayspace::app
