// vk::Status carries a failed Vulkan call's VkResult and name as values, and one line for users.
#include <doctest/doctest.h>

#include <memory>
#include <utility>

#include "rayspace/gpu/vulkan.h"

namespace rayspace {
namespace {

TEST_CASE("status: a failed call's message names the call, the result and its number") {
  const vk::Status s = vk::Status::Fail("vkCreateDevice(physical_, &dci, nullptr, &device_)", VK_ERROR_INITIALIZATION_FAILED);
  CHECK_FALSE(s);
  CHECK(s.result == VK_ERROR_INITIALIZATION_FAILED);
  CHECK(s.call == "vkCreateDevice");
  CHECK(s.message == "vkCreateDevice failed: VK_ERROR_INITIALIZATION_FAILED (-3)");
  // A result without a name in the table still shows its number.
  const vk::Status u = vk::Status::Fail("vkFoo", static_cast<VkResult>(-12345));
  CHECK(u.call == "vkFoo");
  CHECK(u.message == "vkFoo failed: VkResult (-12345)");
}

TEST_CASE("status: a failure that is not a Vulkan call's has no result and no call") {
  const vk::Status s = vk::Status::Fail("kernel file 'k.spv' not found");
  CHECK_FALSE(s);
  CHECK(s.result == VK_SUCCESS);
  CHECK(s.call.empty());
  CHECK(s.message == "kernel file 'k.spv' not found");
  const vk::Status ok = vk::Status::Ok();
  CHECK(ok);
  CHECK(ok.result == VK_SUCCESS);
  CHECK(ok.call.empty());
  CHECK(ok.message.empty());
}

TEST_CASE("status: lavapipe refusing an impossible buffer is reported with its VkResult and call") {
  std::unique_ptr<vk::Context> ctx;
  const vk::Status st = vk::Context::Create(-1, ctx);
  INFO("Vulkan: " << st.message);
  REQUIRE(st);  // the build has Vulkan and the bootstrap installs lavapipe
  vk::Buffer b;
  // 2^50 bytes: a transfer buffer (no storage-binding limit applies) that no device can back.
  const vk::Status s = ctx->CreateBuffer(std::size_t{1} << 50, b, /*storage=*/false);
  INFO("status: " << s.message);
  REQUIRE_FALSE(s);
  CHECK(s.result == VK_ERROR_OUT_OF_DEVICE_MEMORY);
  CHECK(s.call == "vkCreateBuffer");
  CHECK(s.message == "vkCreateBuffer failed: VK_ERROR_OUT_OF_DEVICE_MEMORY (-2)");
  CHECK(b.handle() == VK_NULL_HANDLE);  // nothing was handed out
}

TEST_CASE("status: a storage buffer beyond the binding limit is refused before any Vulkan call") {
  std::unique_ptr<vk::Context> ctx;
  REQUIRE(vk::Context::Create(-1, ctx));
  ctx->LimitForTesting(4096, 0);
  vk::Buffer b;
  const vk::Status s = ctx->CreateBuffer(8192, b);
  REQUIRE_FALSE(s);
  CHECK(s.result == VK_SUCCESS);
  CHECK(s.call.empty());
  CHECK(s.message.find("8192 bytes exceeds the lowered binding limit 4096") != std::string::npos);
}

TEST_CASE("status: an image with a side of 0 or beyond maxImageDimension2D is refused before any Vulkan call") {
  std::unique_ptr<vk::Context> ctx;
  REQUIRE(vk::Context::Create(-1, ctx));
  for (const auto& [w, h] : {std::pair<std::uint32_t, std::uint32_t>{0, 64}, {64, 0}, {1u << 30, 1}}) {
    CAPTURE(w);
    CAPTURE(h);
    vk::Image im;
    const vk::Status s = ctx->CreateImage(VK_FORMAT_R32_UINT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT,
                                          VK_IMAGE_ASPECT_COLOR_BIT, w, h, im);
    REQUIRE_FALSE(s);
    CHECK(s.call.empty());
    CHECK(s.message.find("maxImageDimension2D") != std::string::npos);
    CHECK(im.handle() == VK_NULL_HANDLE);
  }
  vk::Image ok;
  CHECK(ctx->CreateImage(VK_FORMAT_R32_UINT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, VK_IMAGE_ASPECT_COLOR_BIT, 4, 4, ok));
  CHECK(ok.handle() != VK_NULL_HANDLE);
}

}  // namespace
}  // namespace rayspace
