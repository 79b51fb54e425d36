// Runs a program with bytes on its standard input and collects its standard output and error.
#pragma once
#include <string>
#include <vector>

namespace rayspace::plot {

struct ProcessResult {
  bool started = false;  // false: the program could not be run (not found)
  int exit_code = -1;    // -1: killed by a signal
  std::string out, err;
};

// Runs argv[0] (looked up on PATH) with `input` on its standard input; nothing touches the disk.
ProcessResult RunProcess(const std::vector<std::string>& argv, const std::string& input);

// Whether `name` is an executable file in a directory on PATH.
bool OnPath(const std::string& name);

}  // namespace rayspace::plot
