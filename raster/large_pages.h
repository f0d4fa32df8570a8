// LargePageAllocator<T>: a std::allocator for the frame's big arrays (images, G-buffer, receivers)
// that asks the kernel for transparent huge pages.
//
// A 1280x720 frame allocates ~150 MB of per-pixel arrays and touches each once. With 4 KiB pages
// every first touch is a page fault -- on the virtual machines we run on, 2-5 us each, so a single
// frame spent 150-250 ms in the kernel (perf: 27% of the process in exc_page_fault). Blocks of
// kLargePageBytes or more are aligned to 2 MiB and marked MADV_HUGEPAGE, so one fault maps 2 MiB
// (measured on the default scene: docs/performance.md, "The default scene"). Where the kernel has
// no transparent huge pages (or the platform no madvise) the hint is ignored and nothing changes
// but the alignment. Contents are not affected: every element is written before it is read (by
// its container, or by Image::resizeParallel where value-initialization is skipped, below), so
// images stay byte-identical.
//
// Thread-safety: stateless; allocate/deallocate are as thread-safe as the C library's allocator.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <utility>

namespace penumbra::raster {

inline constexpr size_t kLargePageBytes = size_t{2} << 20;

// Marks [p, p + bytes) as wanting huge pages (p and bytes multiples of kLargePageBytes). No-op
// where unsupported.
void adviseLargePages(void* p, size_t bytes);

template <class T>
struct LargePageAllocator {
  using value_type = T;

  LargePageAllocator() = default;
  template <class U>
  LargePageAllocator(const LargePageAllocator<U>&) noexcept {}

  // Bytes actually reserved for n elements: small blocks as asked, large ones rounded up to whole
  // large pages (allocate and deallocate agree on it from n alone).
  static size_t reservedBytes(size_t n) {
    const size_t bytes = n * sizeof(T);
    if (bytes < kLargePageBytes) return bytes;
    return (bytes + kLargePageBytes - 1) / kLargePageBytes * kLargePageBytes;
  }

  T* allocate(size_t n) {
    if (n > static_cast<size_t>(-1) / sizeof(T) / 2) throw std::bad_array_new_length();
    const size_t bytes = n * sizeof(T);
    if (bytes < kLargePageBytes) return static_cast<T*>(::operator new(bytes, std::align_val_t{alignof(T)}));
    const size_t reserved = reservedBytes(n);
    void* p = std::aligned_alloc(kLargePageBytes, reserved);
    if (!p) throw std::bad_alloc();
    adviseLargePages(p, reserved);
    return static_cast<T*>(p);
  }

  void deallocate(T* p, size_t n) noexcept {
    if (n * sizeof(T) < kLargePageBytes) {
      ::operator delete(p, std::align_val_t{alignof(T)});
      return;
    }
    std::free(p);
  }

  // Value-initialization without arguments (vector::resize(n)) leaves the element as the allocation
  // made it, for trivially destructible T (implicit-lifetime types: the pixels and records we
  // store): Image::resizeParallel writes every element right after, from several threads, instead
  // of one thread writing them all first. Every other construction is the ordinary one.
  template <class U>
  void construct(U* p) noexcept {
    static_assert(std::is_trivially_destructible_v<U>, "LargePageAllocator: value-init skipped only for plain data");
    (void)p;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }

  template <class U>
  friend bool operator==(const LargePageAllocator&, const LargePageAllocator<U>&) noexcept {
    return true;
  }
};

}  // namespace penumbra::raster
