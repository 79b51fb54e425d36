// Buffers and images take ranges of pooled blocks of device memory (gpu/include/rayspace/gpu/memory.h):
// a frame's thousands of buffers stay far below maxMemoryAllocationCount, ranges never overlap,
// freed ranges and large blocks are reused, and a device allowing fewer blocks is refused by name.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include "rayspace/gpu/memory.h"
#include "rayspace/gpu/requirements.h"
#include "rayspace/gpu/vulkan.h"
#include "test_settings.h"

namespace rayspace {
namespace {

std::unique_ptr<vk::Context> MakeContext() {
  std::unique_ptr<vk::Context> ctx;
  const vk::Status st = vk::Context::Create(-1, ctx);
  INFO("Vulkan: " << st.message);
  REQUIRE(st);
  return ctx;
}

TEST_CASE("memory: a thousand buffers share a block, keep their own bytes, and give their ranges back") {
  auto ctx = MakeContext();
  const std::size_t before = ctx->memory_allocations();
  {
    std::vector<vk::Buffer> buffers(1000);
    for (std::size_t i = 0; i < buffers.size(); ++i) {
      REQUIRE(ctx->CreateBuffer(4 * (1 + i % 37), buffers[i]));
      std::vector<std::uint32_t> v(1 + i % 37);
      std::iota(v.begin(), v.end(), static_cast<std::uint32_t>(i * 1000));
      REQUIRE(buffers[i].Upload(v));
    }
    CHECK(ctx->memory_allocations() <= before + 1);  // one vkAllocateMemory per buffer before pooling
    bool intact = true;
    for (std::size_t i = 0; i < buffers.size(); ++i) {
      std::vector<std::uint32_t> v;
      REQUIRE(buffers[i].Download(1 + i % 37, v));
      for (std::size_t k = 0; k < v.size(); ++k) intact &= v[k] == i * 1000 + k;
    }
    CHECK(intact);  // no two ranges overlap
  }
  // Released: one empty block kept for the next pass, and reused by it.
  CHECK(ctx->memory_allocations() <= before + 1);
  vk::Buffer again;
  REQUIRE(ctx->CreateBuffer(4096, again));
  CHECK(ctx->memory_allocations() <= before + 1);
}

TEST_CASE("memory: a new storage buffer reads as poison, even in a range another buffer just filled") {
  auto ctx = MakeContext();
  const std::vector<std::uint32_t> right(1000, 1u);  // a flag a forgetful kernel would get right by luck
  {
    vk::Buffer first;
    REQUIRE(ctx->CreateBuffer(right.size() * 4, first));
    REQUIRE(first.Upload(right));
  }
  vk::Buffer reused;  // the pool hands the freed range out again
  REQUIRE(ctx->CreateBuffer(right.size() * 4 + 2, reused));
  REQUIRE(reused.mapped());
  std::vector<std::uint32_t> v;
  REQUIRE(reused.Download(right.size(), v));
  CHECK(std::count(v.begin(), v.end(), vk::Buffer::kPoisonWord) == static_cast<std::ptrdiff_t>(v.size()));
  // As a float the poison is a NaN, which no bitwise or ULP comparison takes for a computed value.
  float f;
  std::memcpy(&f, &vk::Buffer::kPoisonWord, 4);
  CHECK(f != f);
}

TEST_CASE("memory: a buffer larger than half a block has a block of its own, kept for the next of its size") {
  auto ctx = MakeContext();
  const std::size_t before = ctx->memory_allocations(), peak_before = ctx->peak_memory_allocations();
  const std::size_t big = vk::MemoryPool::kBlockBytes / 2 + 4096;
  const std::vector<std::uint32_t> right(big / 4, 1u);
  {
    vk::Buffer b;
    REQUIRE(ctx->CreateBuffer(big, b));
    CHECK(ctx->memory_allocations() == before + 1);
    REQUIRE(b.Upload(right));
  }
  // Kept, as the parts of a split pass ask for the same buffers again.
  CHECK(ctx->memory_allocations() == before + 1);
  {
    vk::Buffer again;  // a part's last, smaller buffer still fits the kept block
    REQUIRE(ctx->CreateBuffer(big - 2048, again));
    CHECK(ctx->memory_allocations() == before + 1);
    // The kept block's old contents do not show through: a new storage buffer reads as poison.
    std::vector<std::uint32_t> v;
    REQUIRE(again.Download(1000, v));
    CHECK(std::count(v.begin(), v.end(), vk::Buffer::kPoisonWord) == 1000);
  }
  {
    // A request the kept block cannot hold frees it first: keeping never adds to the most held at once.
    vk::Buffer larger;
    REQUIRE(ctx->CreateBuffer(3 * big, larger, /*storage=*/false));
    CHECK(ctx->memory_allocations() == before + 1);
  }
  CHECK(ctx->peak_memory_allocations() <= std::max(peak_before, before + 1));
}

TEST_CASE("memory: a device allowing one block refuses the second, naming maxMemoryAllocationCount") {
  rayspace::test::TestSettings settings;
  settings->device_lacks = {{"maxMemoryAllocationCount", 1}};
  auto ctx = MakeContext();
  settings->device_lacks = {};
  vk::Buffer buffer;
  REQUIRE(ctx->CreateBuffer(64, buffer));
  vk::Image image;  // images never share a block with buffers
  const vk::Status st = ctx->CreateImage(VK_FORMAT_R32_UINT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, VK_IMAGE_ASPECT_COLOR_BIT, 8, 8, image);
  CHECK_FALSE(st);
  CHECK(st.message.find("maxMemoryAllocationCount is 1") != std::string::npos);
}

}  // namespace
}  // namespace rayspace

namespace rayspace {
namespace {

TEST_CASE("memory: without mappable device-local memory, storage buffers are device-local and staged") {
  rayspace::test::TestSettings settings;
  settings->device_lacks = {{"mappableDeviceLocal", 0}};
  auto ctx = MakeContext();
  vk::Buffer b;
  REQUIRE(ctx->CreateBuffer(4 * 1000, b));
  settings->device_lacks = {};
  CHECK_FALSE(b.mapped());
  std::vector<std::uint32_t> v(1000);
  std::iota(v.begin(), v.end(), 7u);
  REQUIRE(b.Upload(v));
  std::vector<std::uint32_t> back;
  REQUIRE(b.Download(1000, back));
  CHECK(back == v);
  REQUIRE(b.Zero());
  REQUIRE(b.Download(1000, back));
  CHECK(std::all_of(back.begin(), back.end(), [](std::uint32_t x) { return x == 0; }));
  vk::Buffer readback;  // read-back targets stay host-visible
  REQUIRE(ctx->CreateBuffer(64, readback, /*storage=*/false));
  CHECK(readback.mapped());
}

}  // namespace
}  // namespace rayspace
