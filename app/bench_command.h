#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "rayspace/exit_codes.h"
#include "rayspace/frame/faithful_args.h"

namespace rayspace::app {

struct BenchArgs {
  std::vector<std::string> scenes;
  std::string data, json;
  std::string sizes = "512x512";
  std::string configs;  // empty: every configuration (bench_configs.h)
  int repetitions = 3, threads = 0, device = -1;
  std::map<std::string, std::uint64_t> device_lacks;  // --device-lacks (test use)
  bool progress = false;
  FaithfulArgs faithful;  // the thesis's hierarchy, rays and objects: every configuration takes them
};

// Runs `rayspace bench`: every configuration on every scene at every size, in this process, each frame
// through render's code path with the oracle off; prints one table (median frame time, its ratio to
// Embree's, total tests, tests/s, peak memory, digest) and, with several sizes, how time grows with
// pixels. kOk, or kDivergence when configurations of one tracer (or repetitions of one) gave different
// frame digests.
ExitCode RunBench(const BenchArgs& args);

}  // namespace rayspace::app
