// Large arrays in huge pages (rayspace/large_memory.h, app/large_new.cpp): 2 MiB-aligned, every byte
// writable, advised so that the kernel may back them by huge pages. Whether it does depends on the
// system: where transparent huge pages are "madvise" or "always", the mapping holding the array must
// be eligible (smaps' THPeligible), which it is not without the advice under "madvise".
#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "rayspace/emu/uninit_vector.h"
#include "rayspace/large_memory.h"

namespace rayspace {
namespace {

bool Aligned(const void* p) { return reinterpret_cast<std::uintptr_t>(p) % kLargeBytes == 0; }

std::string ThpMode() {
  std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string s;
  std::getline(f, s);
  const auto open = s.find('['), close = s.find(']');
  return open == std::string::npos || close == std::string::npos ? std::string() : s.substr(open + 1, close - open - 1);
}

// smaps' THPeligible of the mapping holding p: 1, 0, or -1 when smaps does not say.
int ThpEligible(const void* p) {
  std::ifstream f("/proc/self/smaps");
  const auto at = reinterpret_cast<std::uintptr_t>(p);
  std::string line;
  bool inside = false;
  while (std::getline(f, line)) {
    std::uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> lo >> dash >> hi && dash == '-') {
      inside = lo <= at && at < hi;
      continue;
    }
    if (inside && line.rfind("THPeligible:", 0) == 0) return std::stoi(line.substr(12));
  }
  return -1;
}

}  // namespace

TEST_CASE("large memory: aligned to 2 MiB, every byte writable, null when the heap cannot give it") {
  void* p = AllocateLarge(3 * kLargeBytes / 2);
  REQUIRE(p != nullptr);
  CHECK(Aligned(p));
  std::memset(p, 0x5A, 3 * kLargeBytes / 2);
  CHECK(static_cast<unsigned char*>(p)[3 * kLargeBytes / 2 - 1] == 0x5A);
  FreeLarge(p);
  CHECK(TryAllocateLarge(SIZE_MAX) == nullptr);
  CHECK(TryAllocateLarge(SIZE_MAX / 2) == nullptr);
  CHECK_THROWS_AS(AllocateLarge(SIZE_MAX / 2), std::bad_alloc);
}

TEST_CASE("large memory: operator new and UninitVector put large arrays there, small ones on the heap") {
  const std::unique_ptr<char[]> big(new char[kLargeBytes + 1]);
  CHECK(Aligned(big.get()));
  std::vector<std::uint32_t> v(kLargeBytes / 4);
  CHECK(Aligned(v.data()));
  emu::UninitVector<std::uint32_t> u(kLargeBytes / 4);
  CHECK(Aligned(u.data()));
  // Small arrays stay ordinary: 2 MiB for every small vector would be memory thrown away.
  int small_aligned = 0;
  std::vector<std::unique_ptr<char[]>> small;
  for (int i = 0; i < 8; ++i) {
    small.emplace_back(new char[4096]);
    small_aligned += Aligned(small.back().get());
  }
  CHECK(small_aligned < 8);
}

TEST_CASE("large memory: the mapping is eligible for huge pages where the system grants them") {
  const std::string mode = ThpMode();
  if (mode != "madvise" && mode != "always") {
    MESSAGE("transparent huge pages are '" << mode << "' here: nothing to check");
    return;
  }
  std::vector<std::uint8_t> v(4 * kLargeBytes, 1);
  const int eligible = ThpEligible(v.data());
  if (eligible < 0) {
    MESSAGE("smaps has no THPeligible field: nothing to check");
    return;
  }
  CHECK(eligible == 1);
}

}  // namespace rayspace
