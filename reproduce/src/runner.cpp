#include "rayspace/reproduce/runner.h"
#include "rayspace/settings.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <exception>
#include <mutex>
#include <set>
#include <thread>

#include <unistd.h>

#include <fmt/format.h>

namespace rayspace::reproduce {
namespace {

// "[rayspace] reproduce: k of n done, running A, B; elapsed, ETA", in the style of a frame's progress:
// rewritten in place on a terminal, a line per change otherwise.
class Progress {
 public:
  Progress(bool on, std::size_t total) : on_(on), tty_(on && isatty(STDERR_FILENO)), total_(total) {}
  void Start(const std::string& name) {
    std::lock_guard<std::mutex> lock(mutex_);
    running_.insert(name);
    Line();
  }
  void Finish(const std::string& name) {
    std::lock_guard<std::mutex> lock(mutex_);
    running_.erase(name);
    ++done_;
    Line();
    if (tty_ && done_ == total_) std::fprintf(stderr, "\n");
  }

 private:
  void Line() const {
    if (!on_) return;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    std::string running;
    for (const std::string& n : running_) running += (running.empty() ? "" : ", ") + n;
    const std::string eta = done_ == 0 || done_ >= total_ ? fmt::format("elapsed {:.1f} s", s)
                                                          : fmt::format("elapsed {:.1f} s, ETA {:.1f} s", s,
                                                                        s / static_cast<double>(done_) * static_cast<double>(total_ - done_));
    const std::string what = running.empty() ? "" : ", running " + running;
    std::fprintf(stderr, "%s[rayspace] reproduce: %zu of %zu done%s; %s%s", tty_ ? "\r\033[K" : "", done_, total_, what.c_str(),
                 eta.c_str(), tty_ ? "" : "\n");
    std::fflush(stderr);
  }

  bool on_, tty_;
  std::size_t total_, done_ = 0;
  std::set<std::string> running_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

Result RunOne(const Planned& p, const FrameFn& frame) {
  FrameOutput out = frame(p.config, p.scene->scene, p.scene->buffers);
  return {p.key, p.scene->digest, p.config, std::move(out.counts), std::move(out.statistics), std::move(out.timings)};
}

// Writes each result as it finishes, one at a time. --stop-after interrupts here, as Ctrl-C would,
// with exactly K results written and no other job's file half-made.
class Writer {
 public:
  explicit Writer(const RunOptions& options) : options_(options) {}
  void Write(const Result& r) {
    std::lock_guard<std::mutex> lock(mutex_);
    WriteResult(options_.out, r);
    if (options_.stop_after > 0 && ++written_ == options_.stop_after) std::raise(SIGINT);
  }

 private:
  const RunOptions& options_;
  std::mutex mutex_;
  int written_ = 0;
};

}  // namespace

void RunPlanned(const std::vector<Planned>& todo, const RunOptions& options, const FrameFn& frame) {
  Progress progress(options.progress, todo.size());
  std::atomic<std::size_t> next{0};
  Writer writer(options);
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    for (std::size_t i; !failed && (i = next++) < todo.size();) {
      try {
        progress.Start(todo[i].config.Name());
        writer.Write(RunOne(todo[i], frame));
        progress.Finish(todo[i].config.Name());
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        failed = true;
      }
    }
  };
  std::vector<std::thread> threads;
  const int jobs = std::max(1, std::min<int>(options.jobs, static_cast<int>(todo.size())));
  const Settings& settings = CurrentSettings();  // each job runs with the caller's
  for (int j = 1; j < jobs; ++j)
    threads.emplace_back([&] {
      const SettingsInForce in_force(settings);
      worker();
    });
  worker();
  for (std::thread& t : threads) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace rayspace::reproduce
