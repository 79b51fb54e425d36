// The Vulkan work of one pass call as `rayspace export` writes it out: every storage buffer the call
// creates, what the host writes into it and reads back, and each dispatch (pipeline, workgroups, push
// constants, bindings) in the order its submit ran it. Recorded through vk::Observer while the call
// runs on the Vulkan backend.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rayspace/gpu/vulkan.h"

namespace rayspace::app {

struct RecordedPipeline {
  std::string pass;  // the kernel's pass (pass_registry.h)
  std::vector<std::uint32_t> spirv;
  std::uint32_t bindings = 0;
  std::array<std::uint32_t, 3> spec{};  // specialization constants: planted fault, local size, strict math
};

// Where a read-back lands among the call's outputs; no output: a value the host uses itself (a
// count, block sums) before it reads or dispatches more.
struct Landing {
  std::string output;  // as the saved call names it (verify/call_codec.h)
  std::size_t offset = 0, element_bytes = 4;
};

enum class StepKind { kBuffer, kWrite, kZero, kDispatch, kSubmit, kRead, kFree };

struct RecordedStep {
  StepKind kind = StepKind::kBuffer;
  std::uint32_t id = 0;                // the buffer; a dispatch's pipeline
  std::size_t bytes = 0;               // the buffer's size; bytes written or read
  std::vector<std::uint8_t> data;      // bytes written or read; a dispatch's push constants
  std::vector<std::uint32_t> buffers;  // a dispatch's bindings, in binding order
  std::uint32_t gx = 0, gy = 0;        // a dispatch's workgroups
  Landing landing;                     // a read
};

class Recording final : public vk::Observer {
 public:
  // Tells where `bytes` bytes at `dst` lie among the call's outputs, if they do.
  using Resolver = std::function<std::optional<Landing>(const void* dst, std::size_t bytes)>;
  // Buffers, host accesses, dispatches and submits count from Start to Stop; kernels always.
  void Start(Resolver resolve);
  void Stop();
  const std::vector<RecordedStep>& steps() const { return steps_; }
  const std::vector<RecordedPipeline>& pipelines() const { return pipelines_; }
  // Non-empty when the call did something a replay of these steps would not repeat.
  const std::string& problem() const { return problem_; }

  void KernelCreated(const vk::Kernel& k, std::span<const std::uint32_t> spirv, std::span<const std::uint32_t> spec) override;
  void BufferCreated(const vk::Buffer& b) override;
  void BufferDestroyed(const vk::Buffer& b) override;
  void BufferWritten(const vk::Buffer& b, const void* src, std::size_t bytes) override;
  void BufferRead(const vk::Buffer& b, const void* dst, std::size_t bytes) override;
  void Dispatched(const vk::Recorder& r, const vk::Kernel& k, std::span<const vk::Buffer* const> buffers,
                  std::span<const std::uint8_t> push, std::uint32_t gx, std::uint32_t gy) override;
  void Submitted(const vk::Recorder& r) override;

 private:
  // The id of a buffer made during the recording; notes a problem for any other.
  std::optional<std::uint32_t> Id(const vk::Buffer& b);
  bool active_ = false;
  Resolver resolve_;
  std::string problem_;
  std::vector<RecordedStep> steps_;
  std::vector<RecordedPipeline> pipelines_;
  std::map<const vk::Kernel*, std::uint32_t> kernels_;  // index into pipelines_
  std::map<VkBuffer, std::uint32_t> live_;              // buffers alive now, by handle
  std::uint32_t next_buffer_ = 0;
  std::map<const vk::Recorder*, std::vector<RecordedStep>> pending_;  // dispatches recorded, not yet submitted
};

}  // namespace rayspace::app
