// Sub-allocation of device memory. A device allows a few thousand vkAllocateMemory objects at once
// (maxMemoryAllocationCount: 4096 on many GPUs) and each costs a kernel call, while a frame creates
// thousands of buffers; so memory comes in blocks of kBlockBytes per memory type and kind (buffers and
// optimal-tiling images never share a block: bufferImageGranularity), host-visible blocks mapped
// once, and buffers and images take aligned ranges of them (first fit, freed ranges merged). A
// request larger than half a block gets a block of its own. One empty block per memory type and kind
// is kept for the next pass; the others are freed. Released blocks of their own are kept too, up to
// kRetainBytes in all, and reused by a request of at least half their size: a pass split in parts
// asks for the same large buffers part after part, and memory a driver has to fault in and clear
// again for every part costs more than the kernels on a CPU device (lavapipe). A request no kept
// block fits frees them all first, so keeping never adds to the most memory held at once.
#pragma once
#include <cstdint>
#include <map>
#include <vector>

#include <vulkan/vulkan.h>

#include "rayspace/gpu/vulkan.h"

namespace rayspace::vk {

class MemoryPool {
 public:
  static constexpr VkDeviceSize kBlockBytes = VkDeviceSize{64} << 20;
  static constexpr VkDeviceSize kRetainBytes = VkDeviceSize{512} << 20;

  using Range = MemoryRange;  // what a buffer or image binds and, in host-visible memory, maps

  MemoryPool() = default;
  MemoryPool(const MemoryPool&) = delete;
  MemoryPool& operator=(const MemoryPool&) = delete;
  ~MemoryPool();
  // max_allocations: maxMemoryAllocationCount (as the device reports it, or as a test fakes it).
  void Init(VkDevice device, std::uint32_t max_allocations) {
    device_ = device;
    max_allocations_ = max_allocations;
  }

  // A range satisfying `req` in memory type `type`; `image` ranges come from image blocks. Fails
  // naming vkAllocateMemory, or maxMemoryAllocationCount when a new block would exceed it.
  Status Allocate(const VkMemoryRequirements& req, std::uint32_t type, bool host_visible, bool image, Range& out);
  void Release(const Range& r);

  // vkDeviceMemory objects alive now, and the most alive at once (for tests and reports).
  std::size_t allocations() const;
  std::size_t peak_allocations() const { return peak_; }

 private:
  struct Block {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize size = 0;
    void* mapped = nullptr;
    std::uint32_t type = 0;
    bool image = false, dedicated = false;
    std::map<VkDeviceSize, VkDeviceSize> free;  // offset -> length, no two adjacent
    std::size_t ranges = 0;                      // ranges handed out and not released
  };
  bool TakeFrom(Block& b, const VkMemoryRequirements& req, VkDeviceSize& offset);
  Status NewBlock(VkDeviceSize size, std::uint32_t type, bool host_visible, bool image, bool dedicated, std::uint32_t& index);
  void FreeBlock(std::uint32_t index);
  bool Kept(const Block& b) const { return b.memory && b.dedicated && b.ranges == 0; }
  // A kept block of type and kind that holds `size` and is at most twice it, or false.
  bool TakeKept(VkDeviceSize size, std::uint32_t type, bool host_visible, bool image, std::uint32_t& index);
  void FreeKept();

  VkDevice device_ = VK_NULL_HANDLE;
  std::uint32_t max_allocations_ = 4096;
  std::vector<Block> blocks_;  // freed blocks stay as empty slots (memory null), so indices hold
  std::size_t peak_ = 0;
  VkDeviceSize kept_bytes_ = 0;  // in released blocks of their own
};

}  // namespace rayspace::vk
