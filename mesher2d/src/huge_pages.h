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

// Asks for huge pages on the 2 MiB-aligned part of [p, p + bytes). Below 4 MiB it does
// nothing: at most one huge page could be gained, and a small array stays in cache anyway.
inline void advise_huge_pages([[maybe_unused]] const void* p, [[maybe_unused]] std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21;
  if (bytes < 2 * kHuge) return;
  const auto a = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t lo = (a + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t hi = (a + bytes) & ~(kHuge - 1);
  if (hi > lo) (void)madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);  // advice: failure is harmless
#endif
}

// v.reserve(n), then the advice on the whole capacity (the untouched part is what gains:
// call it before the elements are written).
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
  v.reserve(n);
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

}  // namespace uvmesh::m2d::detail
