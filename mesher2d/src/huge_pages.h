// Transparent huge pages for the kernel's large arrays (internal header of mesher2d).
//
// Why: the Delaunay kernel and the field-point insertion touch their triangle and point
// arrays in a spatially coherent but still scattered order (BRIO rounds, §7.3.2 walks,
// cavities). With 4 KiB pages, an array of a few hundred MB needs tens of thousands of
// TLB entries and takes one page fault per 4 KiB on first touch; perf counted the page
// faults alone at 5-8% of a 1e6-point triangulation. Debian's kernel grants 2 MiB pages
// to ranges that ask for them (transparent_hugepage = madvise), so the big arrays ask
// before they are first touched.
//
// This is advice only: the memory stays ordinary std::vector storage, the call changes no
// data, and where it is not available (another OS, THP "never", a small array) nothing
// happens. It uses the C library's madvise (POSIX), no other library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace uvmesh::m2d::detail {

// Asks for huge pages on [p, p + bytes) (page-aligned outwards; the advice covers whole
// mappings, so the allocator's header page before p is included). Below 1 MiB it does
// nothing: a small array stays in cache and costs few faults anyway.
//
// A 2 MiB page can only back a 2 MiB-aligned range whose page table is still empty. The
// first such range of a malloc'ed block holds the allocator's header, written before
// this call: it has a 4 KiB page already, so it would stay on 256-512 small pages (512
// faults at about 2 us each on this machine, against 0.2 ms for one huge page).
// MADV_COLLAPSE (Linux 6.1) makes that first range one huge page now (it copies the
// header page in); where it is not available the range just stays on small pages.
inline void advise_huge_pages([[maybe_unused]] const void* p, [[maybe_unused]] std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21, kPage = 4096;
  if (bytes < (kHuge >> 1)) return;
  const auto a = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t lo = a & ~(kPage - 1);
  const std::uintptr_t hi = (a + bytes + kPage - 1) & ~(kPage - 1);
  (void)madvise(reinterpret_cast<void*>(lo), hi - lo,
                MADV_HUGEPAGE);  // advice: failure is harmless
  const std::uintptr_t first = lo & ~(kHuge - 1);
  if (first == lo && first + kHuge <= hi) {
    constexpr int kCollapse = 25;  // MADV_COLLAPSE (Linux 6.1); EINVAL on older kernels: harmless
    (void)madvise(reinterpret_cast<void*>(first), kHuge, kCollapse);
  }
#endif
}

// v.reserve(n), then the advice on the whole capacity (the untouched part is what gains:
// call it before the elements are written). From 1 MiB the capacity is rounded up so
// that glibc's block (the request plus its 16-byte header, rounded to 16, plus 8, in
// whole pages) is a whole number of 2 MiB: Linux places such anonymous mappings on a
// 2 MiB boundary, so every 2 MiB of the array can be one huge page. The rounding only
// reserves address space; what is never written is never backed. With another
// allocator, or a block served from the heap, the advice covers what it can.
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
  constexpr std::size_t kHuge = std::size_t{1} << 21, kHeader = 32;
  if (n > v.capacity() && n * sizeof(T) >= (kHuge >> 1)) {
    const std::size_t bytes = (n * sizeof(T) + kHeader + kHuge - 1) / kHuge * kHuge - kHeader;
    n = bytes / sizeof(T);
  }
  v.reserve(n);
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

// v.assign(n, x) on storage reserved by reserve_huge.
template <class T>
void assign_huge(std::vector<T>& v, std::size_t n, const T& x) {
  reserve_huge(v, n);
  v.assign(n, x);
}

}  // namespace uvmesh::m2d::detail
