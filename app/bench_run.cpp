#include "bench_run.h"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <memory>

#include "peak_memory.h"
#include "rayspace/digest.h"
#include "render_frame.h"

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
  row.digests.push_back(HexDigest(f.result.digest.Frame()));
  row.total_tests = f.stats.total;
  row.tests_performed = f.stats.hierarchy || f.stats.tl || f.stats.grid;  // brute and embree report brute force
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

BenchRow RunBenchConfig(const RenderArgs& base, const BenchConfig& config, const Scene& scene, const SceneBuffers& buffers,
                        int width, int height, int repetitions, bool progress) {
  BenchRow row;
  row.scene = scene.name;
  row.width = width;
  row.height = height;
  row.config = &config;
  RenderArgs args = base;
  ApplyBenchConfig(config, args);
  args.no_oracle = true;
  emu::FrameOptions fo;
  fo.width = width;
  fo.height = height;
  ApplyFaithful(args.faithful, fo);
  row.peak_reset = ResetPeakRss();
  row.start_rss = CurrentRssBytes();
  for (int rep = 0; rep < repetitions; ++rep) {
    const std::unique_ptr<Backend> backend = TryBackend(args, scene, buffers, width, height, row.skipped);
    if (!backend) break;
    Record(row, *RenderOnBackend(args, scene, buffers, fo, *backend));
    if (progress)
      std::fprintf(stderr, "bench: %s %s %s %d/%d: %.1f ms\n", row.scene.c_str(), row.Size().c_str(), config.name.c_str(),
                   rep + 1, repetitions, row.frame_ms.back());
  }
  row.peak_rss = PeakRssBytes();
  return row;
}

}  // namespace rayspace::app
