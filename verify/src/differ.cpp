#include "rayspace/verify/differ.h"

#include <algorithm>
#include <iterator>
#include <bit>
#include <cstring>
#include <chrono>
#include <filesystem>


#include <fmt/format.h>

#include "rayspace/json_text.h"
#include "rayspace/output_file.h"
#include "rayspace/verify/call_codec.h"
#include "rayspace/verify/raster_edges.h"
#include "spec_tally.h"
#include "rayspace/verify/spec_model.h"

namespace rayspace::verify {
namespace {

template <typename F>
double TimeMs(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::string HitsChanged(Tracer& tracer, const std::vector<layout::Ray>& expected, const std::vector<layout::Ray>& actual,
                        bool shadow) {
  if (expected.size() != actual.size()) return "changed (ray counts differ)";
  std::size_t changed = 0;
  if (shadow) {
    std::vector<std::uint32_t> a, b;
    tracer.Occluded(expected, a);
    tracer.Occluded(actual, b);
    for (std::size_t i = 0; i < a.size(); ++i) changed += a[i] != b[i];
  } else {
    std::vector<std::uint64_t> a, b;
    tracer.Closest(expected, a);
    tracer.Closest(actual, b);
    for (std::size_t i = 0; i < a.size(); ++i) changed += a[i] != b[i];
  }
  return changed ? fmt::format("changed for {} rays", changed) : "unchanged";
}

// The surviving pairs of a traversal output: the values of flagged slots (traverse.top/level), or the
// compacted list (traverse.compact.*, reduce); nothing when the method has no pair output.
std::optional<std::vector<std::uint32_t>> SurvivingPairs(const std::string& method, const BufferSet& out) {
  if (method == "reduce" || method == "traverse.compact.top" || method == "traverse.compact.level")
    return out.Get<std::uint32_t>("pairs");
  if (method != "traverse.top" && method != "traverse.level") return std::nullopt;
  const auto flags = out.Get<std::uint8_t>("flags");
  const auto values = out.Get<std::uint32_t>("values");
  std::vector<std::uint32_t> kept;
  for (std::size_t i = 0; i < flags.size() && i < values.size(); ++i)
    if (flags[i]) kept.push_back(values[i]);
  return kept;
}

}  // namespace

std::string PairsChanged(const std::vector<std::uint32_t>& expected, const std::vector<std::uint32_t>& actual,
                         std::optional<PairBases> bases) {
  std::vector<std::uint32_t> e = expected, a = actual, lost, added;
  std::sort(e.begin(), e.end());
  std::sort(a.begin(), a.end());
  std::set_difference(e.begin(), e.end(), a.begin(), a.end(), std::back_inserter(lost));
  std::set_difference(a.begin(), a.end(), e.begin(), e.end(), std::back_inserter(added));
  if (lost.empty() && added.empty())
    return fmt::format("the same {} candidate pairs in another order", expected.size());
  std::string s = fmt::format("{} of the reference's {} candidate pairs lost, {} added", lost.size(), expected.size(), added.size());
  const auto pair = [&](std::uint32_t v) {
    const std::uint32_t node = v >> layout::kPairTriangleBits, tri = v & layout::kPairTriangleMask;
    if (!bases) return fmt::format("(node +{}, triangle +{} from the level's and the batch's first)", node, tri);
    return fmt::format("(node {}, triangle {})", bases->node + node, bases->triangle + tri);
  };
  if (!lost.empty()) s += fmt::format("; first lost: {}", pair(lost.front()));
  if (!added.empty()) s += fmt::format("; first added: {}", pair(added.front()));
  // A lost pair's rays may have hit its triangle: nothing here proves the loss cannot change a hit.
  if (!lost.empty()) s += "; a lost pair may hold a hit (not judged)";
  return s;
}

namespace {

std::string DirName(std::size_t seq, const std::string& label) {
  std::string s = fmt::format("{:04d}-", seq);
  for (char c : label) s += (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-') ? c : '_';
  return s;
}

// A call through the Differ: run on both backends and compared, the actual backend's outputs moved
// back into its result and in-place arrays. The inputs are viewed, not copied: the frame's arrays
// outlive the call and nothing writes them while it runs (each backend decodes its own copy of an
// in-place array).
template <typename C>
typename C::Result Through(Differ& d, const C& c) {
  return DecodeOutputs(d.Call(std::string(C::kName), ViewCall(c)), c);
}

#define RS_DIFF_CALL(C) emu::call::C::Result C(const emu::call::C& c) override { return Through(d_, c); }

class FrameDecorator final : public emu::FramePasses {
 public:
  explicit FrameDecorator(Differ& d) : d_(d) {}
  // The outputs it returns are the actual backend's, so checks of them name that backend.
  std::string Name() const override { return d_.ActualName(); }
  void Label(const std::string& pass) override { d_.SetLabel(pass); }
  RS_FRAME_CALLS(RS_DIFF_CALL)

 private:
  Differ& d_;
};

class HierarchyDecorator final : public emu::HierarchyPasses {
 public:
  explicit HierarchyDecorator(Differ& d) : d_(d) {}
  std::string Name() const override { return d_.ActualName(); }
  void Label(const std::string& pass) override { d_.SetLabel(pass); }
  RS_HIERARCHY_CALLS(RS_DIFF_CALL)

 private:
  Differ& d_;
};

}  // namespace

CallRecord RunAndCompare(const PassMethod& method, const BufferSet& in, Backends& expected, Backends& actual,
                         BufferSet& actual_out, Tracer* hit_tracer, bool relaxed) {
  CallRecord r;
  r.method = method.method;
  r.pass = method.pass(in);
  BufferSet e;
  try {
    // The expected side is a device too with --backends sim,vulkan: its failure stops the call alike.
    r.expected_ms = TimeMs([&] { e = method.run(in, expected); });
    r.actual_ms = TimeMs([&] { actual_out = method.run(in, actual); });
  } catch (const emu::BackendError& err) {
    r.error = err.what();
    r.error_checker = err.checker();
    r.error_finding = err.finding();
    r.error_device_fault = err.device_fault();
    r.equal = false;
    return r;
  }
  for (const auto& [name, blob] : e.blobs()) {
    auto it = actual_out.blobs().find(name);
    RS_CHECK_MSG(it != actual_out.blobs().end(), "pass method {} gave no '{}' on the actual backend", method.method, name);
    r.buffers.push_back(CompareBlobs(r.pass, name, blob, it->second, actual.frame.Name()));
    r.equal &= r.buffers.back().Equal();
  }
  // A diverged raster: on triangle edges, where devices may differ, or inside triangles?
  if (method.method == "raster" && !r.equal && in.Has("frame")) {
    const layout::FrameConstants fc = in.GetOne<layout::FrameConstants>("frame");
    const RasterDifference diff = ClassifyRaster(fc.dims.x, fc.dims.y, e.Get<std::uint32_t>("prim"),
                                                 actual_out.Get<std::uint32_t>("prim"), e.Get<float>("depth"),
                                                 actual_out.Get<float>("depth"));
    r.raster = diff.Summary();
    if (relaxed) {
      // Coverage (the triangle per pixel) free on edges; inside, a depth test a loosely rounded
      // depth may turn; where both sides cover a pixel with the same triangle, the fragment stage's
      // words within its arithmetic's intervals.
      const SpecVerdict flips = ClassifyRasterFlips(in, e, actual_out, true);
      const SpecVerdict fragments = ClassifyRasterFragments(in, e, actual_out, true);
      r.spec = flips.within + flips.beyond == 0 ? fragments.Summary() : "depth tests: " + flips.Summary() + "; fragments: " + fragments.Summary();
      r.within_spec = flips.AllWithin() && fragments.AllWithin();
    }
  }
  if (relaxed && !r.equal && method.method != "raster") {
    const SpecVerdict v = ClassifyWithinSpec(method.method, in, e, actual_out);
    r.spec = v.Summary();
    r.within_spec = v.AllWithin();
  }
  // A diverged pair list: which candidate pairs one side lost or added. A level's pair names its
  // node from the level's base, a top-level one from t0; the reduction sees packed values alone.
  if (const auto ep = r.equal ? std::nullopt : SurvivingPairs(method.method, e)) {
    const auto has = [&in](const char* name) { return in.scalars.contains(name); };
    std::optional<PairBases> bases;
    if (has("b0") && (has("base") || has("t0"))) bases = PairBases{has("base") ? in.U32("base") : in.U32("t0"), in.U32("b0")};
    r.pairs = PairsChanged(*ep, *SurvivingPairs(method.method, actual_out), bases);
  }
  // A diverged ray batch: would the hits change? (Trim's dense rays are what gets traced.)
  if (hit_tracer && method.method == "trim" && !r.equal) {
    r.hits = HitsChanged(*hit_tracer, e.Get<layout::Ray>("rays"), actual_out.Get<layout::Ray>("rays"),
                         in.U32("kind") == layout::kRayShadow);
  }
  return r;
}

Differ::Differ(Backends expected, Backends actual, DiffOptions options)
    : expected_(expected), actual_(actual), options_(std::move(options)) {
  frame_ = std::make_unique<FrameDecorator>(*this);
  hierarchy_ = std::make_unique<HierarchyDecorator>(*this);
}

Differ::~Differ() = default;

emu::FramePasses& Differ::frame() { return *frame_; }
emu::HierarchyPasses& Differ::hierarchy() { return *hierarchy_; }

void Differ::Save(CallRecord& r, const BufferSet& in, const std::string& method_name) const {
  r.saved = (std::filesystem::path(options_.save_dir) / DirName(r.seq, r.label)).string();
  std::error_code ec;
  std::filesystem::create_directories(r.saved, ec);
  if (ec) ThrowInput("{}: cannot create the directory ({})", r.saved, ec.message());
  nlohmann::json cj = nlohmann::json::array();
  for (const BufferComparison& c : r.buffers) {
    nlohmann::json j;
    c.ToJson(j);
    cj.push_back(j);
  }
  const nlohmann::json comparison = {{"pass", r.pass},   {"label", r.label}, {"inject", options_.inject},
                                     {"equal", r.equal}, {"buffers", cj},    {"options", options_.options}};
  // Before the inputs: BufferSet::Save writes pass.json last, so a call whose pass.json exists is whole.
  OutputFile(r.saved + "/comparison.json", {"a saved comparison", false, false, {}}).Commit(JsonText(comparison));
  in.Save(r.saved, method_name);
}

BufferSet Differ::Call(const std::string& method_name, const BufferSet& in) {
  const PassMethod& method = FindPassMethod(method_name);
  BufferSet actual_out;
  CallRecord r;
  try {
    r = RunAndCompare(method, in, expected_, actual_, actual_out, options_.hit_tracer, options_.relaxed);
  } catch (const InputError& e) {
    // After a divergence, what a later pass gets may break its contract (a ray gathered from past the
    // end, an id out of range): a consequence of the divergence already recorded, where the diff stops.
    const bool diverged = std::any_of(calls_.begin(), calls_.end(), [](const CallRecord& c) { return !c.equal && !c.within_spec; });
    if (!diverged) throw;
    throw DiffStop(fmt::format("{}: its inputs, from a pass that diverged, break its contract: {}", label_.empty() ? method_name : label_,
                               e.what()));
  }
  r.seq = calls_.size();
  r.label = label_.empty() ? method_name : label_;
  if (!options_.save_dir.empty()) Save(r, in, method_name);
  calls_.push_back(r);
  const CallRecord& rec = calls_.back();
  if (!rec.error.empty())
    throw DiffStop(fmt::format("{} ({}): the actual backend failed: {}", rec.pass, rec.label, rec.error), rec.error_checker, rec.pass,
                   rec.error_finding, rec.error_device_fault);
  for (const BufferComparison& c : rec.buffers)
    if (!c.Equal() && !rec.within_spec && method.index_outputs.count(c.buffer))
      throw DiffStop(fmt::format("{} ({}): '{}' differs, and later passes index with it", rec.pass, rec.label, c.buffer));
  return actual_out;
}

}  // namespace rayspace::verify
