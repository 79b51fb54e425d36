#include "rayspace/gpu/memory.h"

#include <fmt/format.h>

#include <algorithm>

namespace rayspace::vk {

MemoryPool::~MemoryPool() {
  for (std::uint32_t i = 0; i < blocks_.size(); ++i) FreeBlock(i);
}

std::size_t MemoryPool::allocations() const {
  return static_cast<std::size_t>(
      std::count_if(blocks_.begin(), blocks_.end(), [](const Block& b) { return b.memory != VK_NULL_HANDLE; }));
}

// First fit: the lowest free range that holds `req` once its start is aligned.
bool MemoryPool::TakeFrom(Block& b, const VkMemoryRequirements& req, VkDeviceSize& offset) {
  for (auto it = b.free.begin(); it != b.free.end(); ++it) {
    const VkDeviceSize start = (it->first + req.alignment - 1) / req.alignment * req.alignment;
    const VkDeviceSize end = it->first + it->second;
    if (start + req.size > end) continue;
    const VkDeviceSize before = start - it->first, after = end - (start + req.size);
    const VkDeviceSize at = it->first;
    b.free.erase(it);
    if (before) b.free[at] = before;
    if (after) b.free[start + req.size] = after;
    offset = start;
    ++b.ranges;
    return true;
  }
  return false;
}

bool MemoryPool::TakeKept(VkDeviceSize size, std::uint32_t type, bool host_visible, bool image, std::uint32_t& index) {
  for (std::uint32_t i = 0; i < blocks_.size(); ++i) {
    const Block& b = blocks_[i];
    if (Kept(b) && b.type == type && b.image == image && (b.mapped != nullptr) == host_visible && size <= b.size && b.size / 2 <= size) {
      kept_bytes_ -= b.size;
      index = i;
      return true;
    }
  }
  return false;
}

void MemoryPool::FreeKept() {
  for (std::uint32_t i = 0; i < blocks_.size(); ++i)
    if (Kept(blocks_[i])) FreeBlock(i);
  kept_bytes_ = 0;
}

Status MemoryPool::NewBlock(VkDeviceSize size, std::uint32_t type, bool host_visible, bool image, bool dedicated,
                            std::uint32_t& index) {
  if (allocations() >= max_allocations_) FreeKept();
  if (allocations() >= max_allocations_)
    return Status::Fail(fmt::format("vkAllocateMemory: {} blocks of device memory are alive, maxMemoryAllocationCount is {}",
                                    allocations(), max_allocations_));
  Block b;
  b.size = size;
  b.type = type;
  b.image = image;
  b.dedicated = dedicated;
  VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  mai.allocationSize = size;
  mai.memoryTypeIndex = type;
  if (VkResult r = vkAllocateMemory(device_, &mai, nullptr, &b.memory); r != VK_SUCCESS) return Status::Fail("vkAllocateMemory", r);
  if (host_visible) {
    if (VkResult r = vkMapMemory(device_, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped); r != VK_SUCCESS) {
      vkFreeMemory(device_, b.memory, nullptr);
      return Status::Fail("vkMapMemory", r);
    }
  }
  b.free[0] = size;
  auto slot = std::find_if(blocks_.begin(), blocks_.end(), [](const Block& x) { return x.memory == VK_NULL_HANDLE; });
  if (slot == blocks_.end()) slot = blocks_.insert(blocks_.end(), Block{});
  *slot = std::move(b);
  index = static_cast<std::uint32_t>(slot - blocks_.begin());
  peak_ = std::max(peak_, allocations());
  return Status::Ok();
}

void MemoryPool::FreeBlock(std::uint32_t i) {
  Block& b = blocks_[i];
  if (b.memory == VK_NULL_HANDLE) return;
  if (b.mapped) vkUnmapMemory(device_, b.memory);
  vkFreeMemory(device_, b.memory, nullptr);
  b = Block{};
}

Status MemoryPool::Allocate(const VkMemoryRequirements& req, std::uint32_t type, bool host_visible, bool image, Range& out) {
  const bool dedicated = req.size > kBlockBytes / 2;
  std::uint32_t index = 0;
  VkDeviceSize offset = 0;
  bool found = false;
  for (std::uint32_t i = 0; i < blocks_.size() && !found && !dedicated; ++i) {
    Block& b = blocks_[i];
    // A mapped and an unmapped block of one type are kept apart: a buffer staged because its memory is
    // not to be mapped must not land in mapped memory, nor a staging buffer in unmapped memory.
    if (b.memory && !b.dedicated && b.type == type && b.image == image && (b.mapped != nullptr) == host_visible &&
        TakeFrom(b, req, offset))
      index = i, found = true;
  }
  if (dedicated) {
    found = TakeKept(req.size, type, host_visible, image, index) && TakeFrom(blocks_[index], req, offset);
    if (!found) FreeKept();
  }
  if (!found) {
    if (Status s = NewBlock(dedicated ? req.size : kBlockBytes, type, host_visible, image, dedicated, index); !s) return s;
    if (!TakeFrom(blocks_[index], req, offset)) return Status::Fail("memory pool: a new block does not hold its request");
  }
  const Block& b = blocks_[index];
  out = {b.memory, offset, req.size, b.mapped ? static_cast<char*>(b.mapped) + offset : nullptr, index};
  return Status::Ok();
}

void MemoryPool::Release(const Range& r) {
  if (r.memory == VK_NULL_HANDLE || r.block >= blocks_.size()) return;
  Block& b = blocks_[r.block];
  // Merge with the free neighbours on both sides.
  VkDeviceSize at = r.offset, len = r.size;
  auto next = b.free.lower_bound(at);
  if (next != b.free.begin()) {
    auto prev = std::prev(next);
    if (prev->first + prev->second == at) {
      at = prev->first;
      len += prev->second;
      b.free.erase(prev);
    }
  }
  next = b.free.lower_bound(at + len);
  if (next != b.free.end() && next->first == at + len) {
    len += next->second;
    b.free.erase(next);
  }
  b.free[at] = len;
  if (--b.ranges > 0) return;
  if (b.dedicated) {
    if (kept_bytes_ + b.size <= kRetainBytes)
      kept_bytes_ += b.size;
    else
      FreeBlock(r.block);
    return;
  }
  // An empty block: keep one per type and kind for the next pass, free the rest.
  const bool other_empty = std::any_of(blocks_.begin(), blocks_.end(), [&](const Block& x) {
    return &x != &b && x.memory && !x.dedicated && x.type == b.type && x.image == b.image &&
           (x.mapped != nullptr) == (b.mapped != nullptr) && x.ranges == 0;
  });
  if (other_empty) FreeBlock(r.block);
}

}  // namespace rayspace::vk
