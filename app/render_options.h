// `rayspace render`'s options, registered in one place so that a command that runs render's frames
// (bench) reads its configurations through the very parser `render` uses.
#pragma once
#include <string>

#include "rayspace/frame/render_command.h"

namespace CLI {
class App;
}

namespace rayspace::app {

// Registers the scene argument and every render option on `command`, writing into `args`.
void AddRenderOptions(CLI::App& command, RenderArgs& args);

// Applies `options`, render options separated by spaces ("--algo crsh --path passes"), to `args` as
// `rayspace render SCENE <options>` would: options not named keep args' values. An option render does
// not take, or a bad value, is an InputError naming `options`.
void ApplyRenderOptions(const std::string& options, RenderArgs& args);

}  // namespace rayspace::app
