// An allocator for the large arrays of height sections (heights, attributes, stacks): blocks of
// 2 MiB or more are aligned to 2 MiB and marked for transparent huge pages (madvise) before they
// are first written, so that a ray's walk over a 4096 x 4096 level (16 KiB rows: a new 4 KiB
// page at every row it crosses) hits the TLB instead of walking page tables. Where the system
// keeps huge pages off (or not on Linux) it is a plain aligned allocation: the contents are the
// same either way.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace beamtrace {

/// Bytes of a transparent huge page on x86-64 Linux.
inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

template <typename T>
struct HugePageAllocator {
    using value_type = T;

    HugePageAllocator() = default;
    template <typename U>
    explicit HugePageAllocator(const HugePageAllocator<U>& /*other*/) {}

    [[nodiscard]] T* allocate(std::size_t n) {
        if (n > static_cast<std::size_t>(-1) / sizeof(T)) {
            throw std::bad_array_new_length();
        }
        const std::size_t bytes = n * sizeof(T);
        if (bytes < kHugePageBytes) {
            return static_cast<T*>(::operator new (bytes, std::align_val_t{alignof(T)}));
        }
        // aligned_alloc wants a multiple of the alignment.
        const std::size_t rounded = (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
        void* p = std::aligned_alloc(kHugePageBytes, rounded);
        if (p == nullptr) {
            throw std::bad_alloc();
        }
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        // Advice only: where it is refused the pages stay small.
        static_cast<void>(::madvise(p, rounded, MADV_HUGEPAGE));
#endif
        return static_cast<T*>(p);
    }

    void deallocate(T* p, std::size_t n) noexcept {
        if (n * sizeof(T) < kHugePageBytes) {
            ::operator delete (p, std::align_val_t{alignof(T)});
            return;
        }
        std::free(p);
    }

    template <typename U>
    bool operator==(const HugePageAllocator<U>& /*other*/) const {
        return true;
    }
};

}  // namespace beamtrace
