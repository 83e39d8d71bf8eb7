// The allocator of the fuzz targets that read .vdb files: an allocation over kLargestAllocation throws
// std::bad_alloc, as a release build's allocator does for a size no machine has. OpenVDB allocates a blosc
// chunk's stated compressed size before it reads the chunk; under ASan and libFuzzer's malloc limit a stated size
// of 1e18 bytes would abort the target instead of reaching the reader's bad_alloc handler, which turns it into an
// rtsdf::Error (grid/VdbRead.cpp). Sizes below the bound are allocated as usual, so ASan checks every access.
#include <cstddef>
#include <cstdlib>
#include <new>

namespace {
constexpr std::size_t kLargestAllocation = std::size_t(1) << 30; // 1 GiB: a 64 KiB input never needs more

void* allocate(std::size_t n) {
  if (n > kLargestAllocation) throw std::bad_alloc();
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
} // namespace

void* operator new(std::size_t n) { return allocate(n); }
void* operator new[](std::size_t n) { return allocate(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate(n);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t& t) noexcept { return operator new(n, t); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
