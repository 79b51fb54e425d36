// The pass-by-pass differential harness. A Differ stands between the frame (and the hierarchy
// tracer) and two backends: every pass call runs on the expected backend (the emulator) and the
// actual one (the Vulkan kernels) with the same inputs, every output buffer is compared bitwise, and
// the actual backend's outputs flow on, so each pass is checked on the inputs the GPU would see.
//
// Lifecycle: construct with both backends; hand frame() / hierarchy() to RenderFrame and the tracer;
// run the frame, catching DiffStop; read calls(). A diverged buffer that later passes index with
// (pair streams, ray orders, offsets) stops the run with DiffStop after its call is recorded.
#pragma once
#include <memory>
#include <stdexcept>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rayspace/emu/tracer.h"
#include "rayspace/verify/pass_table.h"

namespace rayspace::verify {

struct CallRecord {
  std::size_t seq = 0;
  std::string pass;    // the kernel pass (as `diff --inject` names it)
  std::string method;  // the pass method (pass_table.h)
  std::string label;   // where in the frame, e.g. "traverse.L2.shadow.b0"
  std::vector<BufferComparison> buffers;
  bool equal = true;
  double expected_ms = 0, actual_ms = 0;
  std::string hits;   // for ray batches that differ: whether any ray's hit changed
  std::string pairs;  // for pair lists that differ: the candidate pairs lost and added (PairsChanged)
  std::string raster; // for a raster that differs: how many pixels, on triangle edges or inside
  std::string spec;   // under the relaxed device model: how many differing elements a device may produce
  bool within_spec = false;  // differs, but only as a conformant device may (relaxed model only)
  std::string error;  // the actual backend failed on this call
  std::string error_checker;  // ... on a simulated device's checker finding: which checker ("racecheck", ...)
  std::string error_finding;  // ... and the finding's own text
  bool error_device_fault = false;  // ... the device could not finish the call: nothing judged (exit 7)
  std::string saved;  // directory of the saved inputs, when saving
};

class DiffStop : public std::runtime_error {
 public:
  explicit DiffStop(const std::string& what, std::string checker = {}, std::string pass = {}, std::string finding = {},
                    bool device_fault = false)
      : std::runtime_error(what), checker_(std::move(checker)), pass_(std::move(pass)), finding_(std::move(finding)),
        device_fault_(device_fault) {}
  // A stop on a simulated device's checker finding: the checker, the pass whose kernel it was in and
  // the finding's own text.
  const std::string& checker() const { return checker_; }
  const std::string& pass() const { return pass_; }
  const std::string& finding() const { return finding_; }
  // The device could not finish the pass's call (CallRecord::error_device_fault): nothing was judged.
  bool device_fault() const { return device_fault_; }

 private:
  std::string checker_, pass_, finding_;
  bool device_fault_ = false;
};

struct DiffOptions {
  std::string save_dir;           // non-empty: every call's inputs go to save_dir/NNNN-label/
  Tracer* hit_tracer = nullptr;   // traces diverged ray batches to tell whether hits change
  std::string inject;             // the planted fault of the actual backend, recorded with saved inputs
  bool relaxed = false;           // accept differences a conformant device may produce (spec_model.h)
  nlohmann::json options;         // every option that changes what a call computes, recorded for replay
};

// Where a packed pair's node and triangle ids start (layout::kPairTriangleBits).
struct PairBases {
  std::uint32_t node = 0, triangle = 0;
};
// The candidate pairs of a diverged pair list: how many of the reference's (`expected`, compared as
// multisets) the other side lost and how many it added, the first of each decoded by `bases` (or as
// offsets without them).
std::string PairsChanged(const std::vector<std::uint32_t>& expected, const std::vector<std::uint32_t>& actual,
                         std::optional<PairBases> bases);

// Runs `method` on both backends with `in`; `actual_out` receives the actual backend's outputs.
// `relaxed`: a differing call is classified by the relaxed device model (spec_model.h) and, for the
// raster, by where its pixels differ (raster_edges.h).
CallRecord RunAndCompare(const PassMethod& method, const BufferSet& in, Backends& expected, Backends& actual,
                         BufferSet& actual_out, Tracer* hit_tracer = nullptr, bool relaxed = false);

class Differ {
 public:
  Differ(Backends expected, Backends actual, DiffOptions options);
  ~Differ();
  emu::FramePasses& frame();
  emu::HierarchyPasses& hierarchy();
  const std::vector<CallRecord>& calls() const { return calls_; }
  // Runs one call on both backends, records it, returns the actual outputs (throws DiffStop).
  BufferSet Call(const std::string& method, const BufferSet& in);
  void SetLabel(const std::string& label) { label_ = label; }
  std::string ActualName() const { return actual_.frame.Name(); }

 private:
  // Writes the call's comparison and inputs under options_.save_dir; sets r.saved.
  void Save(CallRecord& r, const BufferSet& in, const std::string& method_name) const;
  Backends expected_, actual_;
  DiffOptions options_;
  std::string label_;
  std::vector<CallRecord> calls_;
  std::unique_ptr<emu::FramePasses> frame_;
  std::unique_ptr<emu::HierarchyPasses> hierarchy_;
};

}  // namespace rayspace::verify
