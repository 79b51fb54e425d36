#include "rayspace/export/export_recording.h"

#include <fmt/format.h>

namespace rayspace::app {

void Recording::Start(Resolver resolve) {
  resolve_ = std::move(resolve);
  active_ = true;
}

void Recording::Stop() {
  active_ = false;
  resolve_ = nullptr;
  if (!pending_.empty() && problem_.empty()) problem_ = "dispatches were recorded and never submitted";
}

void Recording::KernelCreated(const vk::Kernel& k, std::span<const std::uint32_t> spirv, std::span<const std::uint32_t> spec) {
  RecordedPipeline p;
  p.pass = k.name();
  p.bindings = k.bindings();
  p.spirv.assign(spirv.begin(), spirv.end());
  for (std::size_t i = 0; i < p.spec.size() && i < spec.size(); ++i) p.spec[i] = spec[i];
  kernels_[&k] = static_cast<std::uint32_t>(pipelines_.size());
  pipelines_.push_back(std::move(p));
}

std::optional<std::uint32_t> Recording::Id(const vk::Buffer& b) {
  auto it = live_.find(b.handle());
  if (it != live_.end()) return it->second;
  if (problem_.empty()) problem_ = "the call used a Vulkan buffer made before it";
  return std::nullopt;
}

void Recording::BufferCreated(const vk::Buffer& b) {
  if (!active_) return;
  live_[b.handle()] = next_buffer_;
  RecordedStep s;
  s.kind = StepKind::kBuffer;
  s.id = next_buffer_++;
  s.bytes = b.size();
  steps_.push_back(std::move(s));
}

void Recording::BufferDestroyed(const vk::Buffer& b) {
  auto it = live_.find(b.handle());
  if (!active_ || it == live_.end()) return;
  RecordedStep s;
  s.kind = StepKind::kFree;
  s.id = it->second;
  live_.erase(it);
  steps_.push_back(std::move(s));
}

void Recording::BufferWritten(const vk::Buffer& b, const void* src, std::size_t bytes) {
  if (!active_) return;
  const std::optional<std::uint32_t> id = Id(b);
  if (!id) return;
  RecordedStep s;
  s.kind = src ? StepKind::kWrite : StepKind::kZero;
  s.id = *id;
  s.bytes = bytes;
  if (src) s.data.assign(static_cast<const std::uint8_t*>(src), static_cast<const std::uint8_t*>(src) + bytes);
  steps_.push_back(std::move(s));
}

void Recording::BufferRead(const vk::Buffer& b, const void* dst, std::size_t bytes) {
  if (!active_) return;
  const std::optional<std::uint32_t> id = Id(b);
  if (!id) return;
  RecordedStep s;
  s.kind = StepKind::kRead;
  s.id = *id;
  s.bytes = bytes;
  s.data.assign(static_cast<const std::uint8_t*>(dst), static_cast<const std::uint8_t*>(dst) + bytes);
  if (resolve_)
    if (std::optional<Landing> l = resolve_(dst, bytes)) s.landing = *l;
  steps_.push_back(std::move(s));
}

void Recording::Dispatched(const vk::Recorder& r, const vk::Kernel& k, std::span<const vk::Buffer* const> buffers,
                           std::span<const std::uint8_t> push, std::uint32_t gx, std::uint32_t gy) {
  if (!active_) return;
  auto kernel = kernels_.find(&k);
  if (kernel == kernels_.end()) {
    if (problem_.empty()) problem_ = fmt::format("kernel {} was made without being recorded", k.name());
    return;
  }
  RecordedStep s;
  s.kind = StepKind::kDispatch;
  s.id = kernel->second;
  s.data.assign(push.begin(), push.end());
  s.gx = gx;
  s.gy = gy;
  for (const vk::Buffer* b : buffers) {
    const std::optional<std::uint32_t> id = Id(*b);
    if (!id) return;
    s.buffers.push_back(*id);
  }
  pending_[&r].push_back(std::move(s));
}

// A submit runs the recorder's dispatches in the order they were recorded; a recorder without any
// (a staged copy) adds nothing.
void Recording::Submitted(const vk::Recorder& r) {
  auto it = pending_.find(&r);
  if (!active_ || it == pending_.end()) return;
  for (RecordedStep& s : it->second) steps_.push_back(std::move(s));
  pending_.erase(it);
  RecordedStep submit;
  submit.kind = StepKind::kSubmit;
  steps_.push_back(std::move(submit));
}

}  // namespace rayspace::app
