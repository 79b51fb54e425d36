// Determinism: every pass output is the same bits for every thread count and schedule. The
// planted-fault cases show the digest comparison can fail.
#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "rayspace/digest.h"
#include "rayspace/emu/frame.h"
#include "rayspace/emu/passes.h"
#include "rayspace/parallel.h"
#include "test_util.h"

using namespace rayspace;

namespace {

struct Run {
  std::uint64_t frame;
  std::vector<DigestLog::Entry> entries;
};

Run Render(const Scene& s, int threads, std::size_t chunk, int w, int h) {
  rayspace::test::TestSettings settings;
  settings->threads = threads;
  settings->chunk = chunk;
  const SceneBuffers b = FlattenScene(s);
  auto tracer = emu::MakeDirectTracer(b, emu::DirectMode::kAuto);
  emu::FrameOptions fo;
  fo.width = w;
  fo.height = h;
  emu::FrameResult r = emu::RenderFrame(s, b, *tracer, fo);
  return {r.digest.Frame(), r.digest.entries()};
}

// The schedule check: compares two runs buffer by buffer and names the first buffer whose hash
// differs ("pass/buffer"), or "" when every hash and the frame digest match.
std::string FirstDifference(const Run& a, const Run& b) {
  if (a.entries.size() != b.entries.size())
    return fmt::format("buffer lists: {} vs {} buffers", a.entries.size(), b.entries.size());
  for (std::size_t i = 0; i < a.entries.size(); ++i) {
    const DigestLog::Entry &x = a.entries[i], &y = b.entries[i];
    if (x.pass != y.pass || x.buffer != y.buffer || x.hash != y.hash) return x.pass + "/" + x.buffer;
  }
  return a.frame == b.frame ? "" : "frame digest";
}

// Schedules compared against one thread: (threads, chunk size); chunk 0 is the static even split.
struct Schedule {
  int threads;
  std::size_t chunk;
};
constexpr Schedule kSchedules[] = {{2, 0}, {3, 0}, {2, 1}, {2, 7}, {3, 33}};

}  // namespace

TEST_CASE("determinism: cornell-mirrors digest is independent of threads and chunk size") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  const Run one = Render(s, 1, 0, 64, 64);
  for (const Schedule& sc : kSchedules) {
    INFO("threads " << sc.threads << ", chunk " << sc.chunk);
    CHECK(FirstDifference(one, Render(s, sc.threads, sc.chunk, 64, 64)) == "");
  }
}

TEST_CASE("determinism: office digest is independent of threads") {
  const Scene s = test::LoadBundled("office.json");
  CHECK(FirstDifference(Render(s, 1, 0, 48, 48), Render(s, 2, 5, 48, 48)) == "");
}

TEST_CASE("planted fault: the digest sees a single flipped bit in any buffer") {
  std::vector<float> a(1000, 0.5f), b = a;
  reinterpret_cast<std::uint32_t*>(b.data())[537] ^= 1u;  // one ULP in one element
  DigestLog la, lb;
  la.Add("pass", "buf", a);
  lb.Add("pass", "buf", b);
  CHECK(la.Frame() != lb.Frame());
  // Same bytes under another pass or buffer name must also differ: the name is part of the digest.
  DigestLog lc;
  lc.Add("pas", "sbuf", a);
  CHECK(la.Frame() != lc.Frame());
}

namespace {

// Contributions to one pixel: one large, then many below half an ulp of it, so that the float sum
// depends on whether the small ones meet the large one one at a time or summed among themselves.
std::vector<float> Contributions() {
  std::vector<float> c(4096, 1.5e-3f);  // ulp(60000) = 2^-8, half of it 1.95e-3
  c[0] = 60000.0f;
  return c;
}

// The fault: a float sum kept per worker thread, each in the order its thread visits its elements,
// the partial sums then added in order of their first element (an OpenMP `reduction(+:)`, or one
// partial per workgroup on a GPU). `split` is set when another thread than the one holding element
// 0 summed at least two elements: then the large element cannot absorb them one by one.
Run FloatReduction(const std::vector<float>& c, const Schedule& sc, bool& split) {
  rayspace::test::TestSettings settings;
  struct Partial {
    std::size_t first, count = 0;
    float sum = 0.0f;
  };
  std::mutex m;
  std::map<std::thread::id, Partial> partials;
  settings->threads = sc.threads;
  settings->chunk = sc.chunk;
  ParallelFor(c.size(), [&](std::size_t i) {
    std::lock_guard lock(m);
    auto [it, fresh] = partials.try_emplace(std::this_thread::get_id(), Partial{i});
    it->second.sum += c[i];
    ++it->second.count;
  });
  settings->threads = 0;
  settings->chunk = 0;
  std::vector<Partial> ordered;
  for (const auto& [id, p] : partials) ordered.push_back(p);
  std::sort(ordered.begin(), ordered.end(), [](const Partial& a, const Partial& b) { return a.first < b.first; });
  split = false;
  std::vector<float> total(1, 0.0f);
  for (const Partial& p : ordered) {
    total[0] += p.sum;
    split |= p.first != 0 && p.count >= 2;
  }
  DigestLog log;
  log.Add("reduce.float", "sum", total);
  return {log.Frame(), log.entries()};
}

// The same contributions through the shade pass: every surface lights pixel 0 with colour 1 (a white
// light straight above at distance 1, no attenuation, diffuse 1), weighted by its contribution.
Run ShadeAccumulation(const std::vector<float>& c, const Schedule& sc, std::vector<std::uint64_t>& accum) {
  rayspace::test::TestSettings settings;
  Scene scene;
  scene.materials.push_back(test::Diffuse("white", glm::vec3(1.0f)));
  LightDesc light;
  light.position = {0, 1, 0};
  scene.lights.push_back(light);
  test::AddQuad(scene, "floor", {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1});
  const SceneBuffers b = FlattenScene(scene);
  const layout::FrameConstants fc = MakeFrameConstants(scene, b, 1, 1);
  std::vector<layout::Surface> surfaces(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    layout::Surface& s = surfaces[i];
    s.position = glm::vec4(0, 0, 0, 1);
    s.normal = glm::vec4(0, 1, 0, 0);
    s.incoming = glm::vec4(0, -1, 0, 0);
    s.weight = glm::vec4(c[i], c[i], c[i], 0);
    s.info = glm::uvec4(0);  // pixel 0, material 0
  }
  const std::vector<std::uint32_t> flags(c.size(), 1u), occluded(c.size(), 0u);
  std::vector<std::uint32_t> offsets(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) offsets[i] = static_cast<std::uint32_t>(i);
  accum.assign(3, 0);
  settings->threads = sc.threads;
  settings->chunk = sc.chunk;
  emu::PassShade({.frame = fc, .surfaces = surfaces, .shadow_flags = flags, .shadow_offsets = offsets, .occluded = occluded,
                  .accum = &accum, .scene = &b});
  settings->threads = 0;
  settings->chunk = 0;
  DigestLog log;
  log.Add("shade", "accum", accum);
  return {log.Frame(), log.entries()};
}

}  // namespace

TEST_CASE("planted fault: an order-dependent float reduction is caught by the schedule check") {
  // What the fixed-point accumulator exists to prevent. The faulty float reduction runs through
  // ParallelFor under the schedules of the tests above; their comparison must name its buffer under
  // every schedule that split the work. The static splits always do, so the check cannot pass blind.
  const std::vector<float> c = Contributions();
  bool split = false;
  const Run serial = FloatReduction(c, {1, 0}, split);
  REQUIRE_FALSE(split);
  for (const Schedule& sc : kSchedules) {
    INFO("threads " << sc.threads << ", chunk " << sc.chunk);
    const Run run = FloatReduction(c, sc, split);
    if (sc.chunk == 0) CHECK(split);  // a static schedule gives every thread a contiguous share
    if (split) CHECK(FirstDifference(serial, run) == "reduce.float/sum");
  }
}

TEST_CASE("determinism: the shade pass's fixed-point accumulator gives the same bits under every schedule") {
  // The contributions the float reduction above loses or keeps depending on the schedule.
  const std::vector<float> c = Contributions();
  std::vector<std::uint64_t> accum;
  const Run serial = ShadeAccumulation(c, {1, 0}, accum);
  // Every contribution counted, the small ones too: c x 2^32, truncated, summed exactly.
  const std::uint64_t large = static_cast<std::uint64_t>(c[0] * layout::kAccumScale);
  const std::uint64_t small = static_cast<std::uint64_t>(c[1] * layout::kAccumScale);
  CHECK(accum[0] == large + (c.size() - 1) * small);
  CHECK(accum[2] == accum[0]);
  for (const Schedule& sc : kSchedules) {
    INFO("threads " << sc.threads << ", chunk " << sc.chunk);
    CHECK(FirstDifference(serial, ShadeAccumulation(c, sc, accum)) == "");
  }
}
