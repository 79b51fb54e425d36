// A vk::Observer is told what a Context does at the Vulkan boundary, in order: what `rayspace export`
// records of one pass call. A trim call (three dispatches in one submit, then its read-backs) is told
// completely; staging buffers, and buffers made while no observer watched, are not told.
#include <doctest/doctest.h>

#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rayspace/gpu/passes.h"
#include "rayspace/gpu/requirements.h"
#include "rayspace/gpu/vulkan.h"
#include "test_settings.h"

namespace rayspace {
namespace {

// Every event as a line: "buffer 3 20", "write 3 20", "zero 3", "read 3 20", "free 3",
// "dispatch trim 2x1 push 12 bindings 5", "submit", "kernel trim 5".
class Log final : public vk::Observer {
 public:
  std::vector<std::string> events;
  std::vector<std::vector<std::uint8_t>> reads;  // the bytes of each read
  void KernelCreated(const vk::Kernel& k, std::span<const std::uint32_t> spirv, std::span<const std::uint32_t> spec) override {
    CHECK(!spirv.empty());
    CHECK(spec.size() == 3);
    events.push_back("kernel " + k.name() + " " + std::to_string(k.bindings()));
  }
  void BufferCreated(const vk::Buffer& b) override {
    ids_[b.handle()] = next_++;
    events.push_back("buffer " + Id(b) + " " + std::to_string(b.size()));
  }
  void BufferDestroyed(const vk::Buffer& b) override { events.push_back("free " + Id(b)); }
  void BufferWritten(const vk::Buffer& b, const void* src, std::size_t bytes) override {
    events.push_back((src ? "write " : "zero ") + Id(b) + (src ? " " + std::to_string(bytes) : ""));
  }
  void BufferRead(const vk::Buffer& b, const void* dst, std::size_t bytes) override {
    events.push_back("read " + Id(b) + " " + std::to_string(bytes));
    reads.emplace_back(static_cast<const std::uint8_t*>(dst), static_cast<const std::uint8_t*>(dst) + bytes);
  }
  void Dispatched(const vk::Recorder&, const vk::Kernel& k, std::span<const vk::Buffer* const> buffers,
                  std::span<const std::uint8_t> push, std::uint32_t gx, std::uint32_t gy) override {
    events.push_back("dispatch " + k.name() + " " + std::to_string(gx) + "x" + std::to_string(gy) + " push " +
                     std::to_string(push.size()) + " bindings " + std::to_string(buffers.size()));
  }
  void Submitted(const vk::Recorder&) override { events.push_back("submit"); }
  std::size_t Count(const std::string& prefix) const {
    std::size_t n = 0;
    for (const std::string& e : events) n += e.rfind(prefix, 0) == 0;
    return n;
  }
  std::size_t First(const std::string& prefix) const {
    for (std::size_t i = 0; i < events.size(); ++i)
      if (events[i].rfind(prefix, 0) == 0) return i;
    return events.size();
  }

 private:
  std::string Id(const vk::Buffer& b) const {
    auto it = ids_.find(b.handle());
    return it == ids_.end() ? std::string("?") : std::to_string(it->second);
  }
  std::map<VkBuffer, int> ids_;
  int next_ = 0;
};

std::unique_ptr<gpu_backend::VulkanPasses> ObservedPasses(Log& log) {
  std::unique_ptr<gpu_backend::VulkanPasses> gpu;
  test::TestSettings settings;
  settings->observer = &log;
  const vk::Status st = gpu_backend::VulkanPasses::Create(-1, {}, gpu);
  INFO("Vulkan: " << st.message);
  REQUIRE(st);
  return gpu;
}

// 5000 slots, every third flagged: two blocks of kScanBlock.
void RunTrim(gpu_backend::VulkanPasses& gpu, emu::Trimmed& out) {
  static std::vector<layout::Ray> rays(5000);
  static std::vector<std::uint32_t> flags(5000);
  for (std::size_t i = 0; i < flags.size(); ++i) {
    flags[i] = i % 3 == 0;
    rays[i].origin_tmin = glm::vec4(static_cast<float>(i), 0, 0, 0);
  }
  emu::call::Trim c;
  c.rays = rays;
  c.flags = flags;
  REQUIRE(gpu.Run(c, out));
}

TEST_CASE("observer: a trim call is told in order: buffers and uploads, three dispatches, one submit, read-backs, frees") {
  Log log;
  auto gpu = ObservedPasses(log);
  std::size_t kernels = 0;
  for (const PassSpec& p : kPasses) kernels += !p.graphics;
  CHECK(log.Count("kernel ") == kernels);
  CHECK(log.First("kernel trim 5") < log.events.size());
  log.events.clear();
  emu::Trimmed out;
  RunTrim(*gpu, out);
  INFO([&] {
    std::string all;
    for (const std::string& e : log.events) all += e + "\n";
    return all;
  }());
  CHECK(log.Count("buffer ") == 5);
  CHECK(log.Count("write ") == 2);  // the flags and the sparse rays
  CHECK(log.Count("dispatch trim 2x1 push 12 bindings 5") == 2);  // block sums and scatter, a workgroup per block
  CHECK(log.Count("dispatch trim 1x1 push 12 bindings 5") == 1);  // the scan of the block sums
  CHECK(log.Count("submit") == 1);
  CHECK(log.Count("read ") == 3);  // block sums, offsets, dense rays
  CHECK(log.Count("free ") == 5);
  CHECK(log.Count("free ?") + log.Count("read ?") + log.Count("write ?") == 0);
  CHECK(log.First("dispatch ") > log.First("write "));
  CHECK(log.First("submit") > log.First("dispatch "));
  CHECK(log.First("read ") > log.First("submit"));
  CHECK(log.First("free ") > log.First("read "));
  // What the host read is what the call returned.
  REQUIRE(log.reads.size() == 3);
  CHECK(log.reads[1].size() == out.offsets.size() * 4);
  CHECK(std::memcmp(log.reads[1].data(), out.offsets.data(), log.reads[1].size()) == 0);
  CHECK(log.reads[2].size() == out.rays.size() * sizeof(layout::Ray));
  CHECK(std::memcmp(log.reads[2].data(), out.rays.data(), log.reads[2].size()) == 0);
}

TEST_CASE("observer: staged host accesses are told once, their staging buffers and copies not at all") {
  rayspace::test::TestSettings settings;
  settings->device_lacks = {{"mappableDeviceLocal", 0}};  // storage buffers the host reaches by staging
  Log log;
  auto gpu = ObservedPasses(log);
  log.events.clear();
  emu::Trimmed out;
  RunTrim(*gpu, out);
  settings->device_lacks = {};
  CHECK(log.Count("buffer ") == 5);  // no staging buffer
  CHECK(log.Count("write ") == 2);
  CHECK(log.Count("read ") == 3);
  CHECK(log.Count("submit") == 1);  // the staging copies' submits carry no dispatch and are not told
}

TEST_CASE("observer: a context made without an observer tells nothing") {
  Log log;
  std::unique_ptr<gpu_backend::VulkanPasses> gpu;
  REQUIRE(gpu_backend::VulkanPasses::Create(-1, {}, gpu));
  test::TestSettings settings;
  settings->observer = &log;  // too late for this context
  emu::Trimmed out;
  RunTrim(*gpu, out);
  CHECK(log.events.empty());
}

}  // namespace
}  // namespace rayspace
