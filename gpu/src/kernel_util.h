// The host-side helpers every kernel's launch code shares: buffers from spans, paged arrays, bindings
// placed by contract number, buffers kept alive until a submit, and launches in parts that fit one
// binding. Private to gpu/src.
#pragma once
#include <algorithm>
#include <array>
#include <cstring>
#include <deque>
#include <span>
#include <vector>

#include <fmt/format.h>

#include "rayspace/contract.h"
#include "rayspace/error.h"
#include "rayspace/gpu/vulkan.h"

namespace rayspace::gpu_backend::detail {

// A buffer holding `v` (at least one element: an empty input still needs something to bind).
template <typename T>
vk::Status MakeFrom(vk::Context& c, std::span<const T> v, vk::Buffer& b) {
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(v.size(), 1) * sizeof(T), b, /*storage=*/true, /*poison=*/false));  // written whole below
  if (v.empty()) return b.Zero();
  return b.Write(v.data(), v.size_bytes());
}

// Records one dispatch, submits it and waits.
inline vk::Status RunKernel(vk::Context& c, const vk::Kernel& k, std::span<const vk::Buffer* const> buffers, const void* push,
                     std::size_t push_size, std::uint32_t invocations) {
  vk::Recorder rec(c);
  RS_TRY(rec.Dispatch(k, buffers, push, push_size, invocations));
  return rec.Submit();
}

// An array read or written at any index, bound as layout::kBufferPages consecutive bindings of `page`
// elements each (gpu/shaders/paged.glsl). Pages are as large as one binding may be.
struct Paged {
  std::array<vk::Buffer, layout::kBufferPages> pages;
  std::uint32_t page = 1;  // elements per page
  template <typename T>
  [[nodiscard]] vk::Status Read(std::span<T> out) const {
    for (std::size_t p = 0, at = 0; p < pages.size() && at < out.size(); ++p, at += page)
      RS_TRY(pages[p].Read(out.data() + at, std::min<std::size_t>(page, out.size() - at) * sizeof(T)));
    return vk::Status::Ok();
  }
};
static_assert(layout::kBufferPages == 4, "paged.glsl declares four bindings per paged array");

// The buffers of one dispatch, each placed at its binding number from rayspace/contract.h.
template <std::uint32_t N>
class Bindings {
 public:
  Bindings& Set(std::uint32_t binding, const vk::Buffer* b) {
    RS_CHECK(binding < N && b);
    bufs_[binding] = b;
    return *this;
  }
  Bindings& Set(std::uint32_t first, const Paged& p) {
    for (std::uint32_t k = 0; k < layout::kBufferPages; ++k) Set(first + k, &p.pages[k]);
    return *this;
  }
  bool Has(std::uint32_t binding) const { return binding < N && bufs_[binding] != nullptr; }
  // Every binding must have been set.
  std::span<const vk::Buffer* const> All() const {
    for (const vk::Buffer* b : bufs_) RS_CHECK(b != nullptr);
    return bufs_;
  }

 private:
  std::array<const vk::Buffer*, N> bufs_{};
};

// `multi` counts the arrays that needed more than one page (for reports and tests).
template <typename T>
vk::Status MakePaged(vk::Context& c, std::span<const T> v, const char* what, Paged& out, std::size_t& multi) {
  const std::size_t per = std::min<std::size_t>(std::max<VkDeviceSize>(1, c.storage_limit() / sizeof(T)), 0x80000000u);
  if (v.size() > per * layout::kBufferPages)
    return vk::Status::Fail(fmt::format("{}: {} elements of {} bytes need more than {} bindings of {} bytes", what, v.size(),
                                        sizeof(T), layout::kBufferPages, c.storage_limit()));
  out.page = static_cast<std::uint32_t>(per);
  if (v.size() > per) ++multi;
  for (std::size_t p = 0; p < layout::kBufferPages; ++p) {
    const std::size_t at = std::min(v.size(), p * per);
    RS_TRY(MakeFrom(c, v.subspan(at, std::min(per, v.size() - at)), out.pages[p]));
  }
  return vk::Status::Ok();
}

// Buffers that must live until a recorder's submit.
class Keep {
 public:
  template <typename T>
  vk::Status From(vk::Context& c, std::span<const T> v, const vk::Buffer*& out) {
    vk::Buffer& b = New();
    RS_TRY(MakeFrom(c, v, b));
    out = &b;
    return vk::Status::Ok();
  }
  // An output buffer of `bytes` whose contents CopyBack() copies to `dst` (null: none).
  vk::Status Output(vk::Context& c, std::size_t bytes, const vk::Buffer*& out, void* dst = nullptr) {
    vk::Buffer& b = New();
    RS_TRY(c.CreateBuffer(std::max<std::size_t>(bytes, 4), b));
    out = &b;
    if (dst && bytes) back_.push_back({&b, dst, bytes});
    return vk::Status::Ok();
  }
  // After the submit.
  [[nodiscard]] vk::Status CopyBack() const {
    for (const Back& k : back_) RS_TRY(k.buf->Read(k.dst, k.bytes));
    return vk::Status::Ok();
  }

 private:
  struct Back {
    const vk::Buffer* buf = nullptr;
    void* dst;
    std::size_t bytes;
  };
  vk::Buffer& New() { return bufs_.emplace_back(); }
  std::deque<vk::Buffer> bufs_;  // a deque: addresses stay valid as it grows
  std::vector<Back> back_;
};

// Calls part(i0, i1) for consecutive ranges covering [0, n) of at most `per` elements (once for an
// empty stream); every range after the first counts as an extra dispatch.
template <typename F>
vk::Status ForParts(std::size_t n, std::size_t per, std::size_t& extra, F&& part) {
  per = std::max<std::size_t>(1, std::min<std::size_t>(per, 0x40000000u));
  std::size_t i0 = 0;
  do {
    const std::size_t i1 = std::min(n, i0 + per);
    if (i0 != 0) ++extra;
    RS_TRY(part(i0, i1));
    i0 = i1;
  } while (i0 < n);
  return vk::Status::Ok();
}

// Blocks of a blocked scan over n elements (one invocation each).
inline std::uint32_t Blocks(std::size_t n) { return static_cast<std::uint32_t>((n + layout::kScanBlock - 1) / layout::kScanBlock); }

template <typename T>
std::span<const T> Slice(std::span<const T> v, std::size_t i0, std::size_t i1) {
  return v.subspan(i0, i1 - i0);
}
template <typename T>
std::span<const T> Slice(const std::vector<T>& v, std::size_t i0, std::size_t i1) {
  return Slice(std::span<const T>(v), i0, i1);
}

// A zeroed output buffer of `bytes` at `binding`, kept by `keep` and copied back to dst (null: not read).
template <std::uint32_t N>
vk::Status Output(vk::Context& c, Keep& keep, Bindings<N>& b, std::uint32_t binding, std::size_t bytes, void* dst) {
  const vk::Buffer* x = nullptr;
  RS_TRY(keep.Output(c, bytes, x, dst));
  RS_TRY(const_cast<vk::Buffer*>(x)->Zero());
  b.Set(binding, x);
  return vk::Status::Ok();
}

// An input array at `binding`, kept by `keep`.
template <std::uint32_t N, typename T>
vk::Status Input(vk::Context& c, Keep& keep, Bindings<N>& b, std::uint32_t binding, std::span<const T> v) {
  const vk::Buffer* x = nullptr;
  RS_TRY(keep.From(c, v, x));
  b.Set(binding, x);
  return vk::Status::Ok();
}

}  // namespace rayspace::gpu_backend::detail
