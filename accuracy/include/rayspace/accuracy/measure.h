// `rayspace accuracy`, the measurement: every precision mode of the cone-sphere and ray-triangle
// tests on the sampled queries against the exact answer, and end to end in the frame.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "rayspace/accuracy/sampler.h"
#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/scene.h"

namespace rayspace::accuracy {

// One mode on one query set: disagreements with the exact answer and time per test.
struct Row {
  std::string test, set, mode;
  std::size_t n = 0, fn = 0, fp = 0, in_plane = 0;  // in_plane: disagreements on rays in the triangle's plane
  double ns = 0;
};

// One mode in the whole frame, against the frame with the exact test.
struct EndToEnd {
  std::string mode;
  double ms = 0;
  std::uint64_t tests = 0;
  std::size_t changed = 0;
};

// The frame's hits and occlusion per batch, its time and its hierarchy (and final) tests.
struct FrameOutcome {
  double ms = 0;
  std::vector<std::vector<std::uint64_t>> hits;
  std::vector<std::vector<std::uint32_t>> occluded;
  std::uint64_t tests = 0;
};

// A precision mode of a test: its decision on sample i.
struct Mode {
  std::string name;
  std::function<bool(std::size_t)> answer;
  bool slow = false;  // exact rationals: timed on a subsample
};
// Each mode on n samples against `truth` (the exact decisions): one row each, FN and FP counted, time
// per test the median of three timed passes of at least `min_time` seconds each (the samples repeated
// until then; `accuracy --min-time`); `in_plane` marks rays in the triangle's plane.
void Evaluate(const std::string& test, const std::string& set, std::size_t n, const std::vector<Mode>& modes,
              const std::vector<char>& truth, std::vector<Row>& rows, double min_time, const std::vector<char>* in_plane = nullptr);
// Rays whose packed hit or occlusion differs between two frames.
std::size_t RaysChanged(const FrameOutcome& a, const FrameOutcome& b);

// Renders the frame with the hierarchy tracer running `passes`.
FrameOutcome RunFrame(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo, emu::HierarchyPasses& passes);

// Each cone-sphere mode on the workload's sampled and near-boundary queries; rows appended.
void MeasureConeModes(const Workload& w, std::vector<Row>& rows, double min_time);
// Each ray-triangle mode likewise, counting disagreements on rays in the triangle's plane.
void MeasureTriModes(const Workload& w, std::vector<Row>& rows, double min_time);
// The frame with each cone-sphere mode in the traversal, against the exact traversal.
std::vector<EndToEnd> ConeEndToEnd(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo);
// The frame with each ray-triangle mode in the final tests (traversal conservative), against exact
// decisions and exact distance order.
std::vector<EndToEnd> TriEndToEnd(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo);

}  // namespace rayspace::accuracy
