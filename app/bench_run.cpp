#include "bench_run.h"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <memory>

#include "rayspace/frame/peak_memory.h"
#include "rayspace/digest.h"
#include "rayspace/frame/render_frame.h"

namespace rayspace::app {
namespace {


// The backend for one repetition, checked to hold the frame; nullptr (and `why`) when it cannot be
// made here.
std::unique_ptr<Backend> TryBackend(const RenderArgs& args, const Scene& scene, const SceneBuffers& buffers, int width,
                                    int height, std::string& why) {
  try {
    auto backend = std::make_unique<Backend>(MakeRenderBackend(args));
    CheckFrameFits(*backend, width, height, ShadowSlotsPerSurface(scene.lights), buffers.triangles.size());
    return backend;
  } catch (const std::exception& e) {
    why = e.what();
    return nullptr;
  }
}

void Record(BenchRow& row, const RenderedFrame& f) {
  row.frame_ms.push_back(f.result.total_ms);
  row.search_ms.push_back(SearchMs(f.phases));
  row.traversal_ms.push_back(TraversalMs(f.phases));
  row.digests.push_back(HexDigest(f.result.digest.Frame()));
  row.total_tests = f.stats.total;
  row.tests_performed = f.stats.hierarchy || f.stats.tl || f.stats.grid;  // brute and embree report brute force
  row.tests_counted = f.stats.tests_counted;
}

}  // namespace

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double BenchRow::MedianMs() const { return Median(frame_ms); }
double BenchRow::MedianSearchMs() const { return Median(search_ms); }
double BenchRow::MedianTraversalMs() const { return Median(traversal_ms); }

BenchRow StartBenchRow(const RenderArgs& base, const BenchConfig& config, const Scene& scene, int width, int height) {
  BenchRow row;
  row.scene = scene.name;
  row.width = width;
  row.height = height;
  row.config = &config;
  row.args = base;
  ApplyBenchConfig(config, row.args);
  row.args.no_oracle = true;
  row.peak_reset = true;
  return row;
}

bool RunBenchRepetition(BenchRow& row, const Scene& scene, const SceneBuffers& buffers, int repetitions, bool progress) {
  if (!row.skipped.empty()) return false;
  emu::FrameOptions fo;
  fo.width = row.width;
  fo.height = row.height;
  ApplyFaithful(row.args.faithful, fo);
  // The high-water mark is reset before each repetition, so the row's peak is its own repetitions'
  // even when the rows' repetitions alternate.
  const bool reset = ResetPeakRss();
  const std::size_t start = CurrentRssBytes();
  const std::unique_ptr<Backend> backend = TryBackend(row.args, scene, buffers, row.width, row.height, row.skipped);
  if (!backend) return false;
  Record(row, *RenderOnBackend(row.args, scene, buffers, fo, *backend));
  const std::size_t peak = PeakRssBytes();
  row.peak_reset = row.peak_reset && reset;
  if (row.frame_ms.size() == 1 || peak > row.peak_rss) {
    row.peak_rss = peak;
    row.start_rss = start;
  }
  if (progress)
    std::fprintf(stderr, "bench: %s %s %s %zu/%d: %.1f ms\n", row.scene.c_str(), row.Size().c_str(), row.config->name.c_str(),
                 row.frame_ms.size(), repetitions, row.frame_ms.back());
  return true;
}

}  // namespace rayspace::app
