// Open-addressing set of 64-bit keys, for the refinement's "edge already analysed" test.
// std::unordered_set allocated a node per key and chased a pointer per lookup: on the
// anisotropic field-point stage (bl:1e-4,0.01, 1e5 triangles) its lookups were 20% of
// the whole mesh() call, nearly all of it cache misses on the nodes. Here a key is one
// 8-byte slot of a flat table (linear probing, Fibonacci hashing on a power-of-two
// size, at most 5/8 full), so a lookup costs one cache line in the common case.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace uvmesh::m2d::detail {

class KeySet64 {
 public:
  // The one value that cannot be stored (it marks an empty slot).
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  // Inserts k; true when it was not there before. k must not be kEmpty.
  bool insert(std::uint64_t k) {
    if (8 * (size_ + 1) > 5 * slots_.size()) grow();
    for (std::size_t i = slot(k);; i = (i + 1) & mask_) {
      std::uint64_t& s = slots_[i];
      if (s == k) return false;
      if (s == kEmpty) {
        s = k;
        ++size_;
        return true;
      }
    }
  }

  bool contains(std::uint64_t k) const {
    if (slots_.empty()) return false;
    for (std::size_t i = slot(k);; i = (i + 1) & mask_) {
      if (slots_[i] == k) return true;
      if (slots_[i] == kEmpty) return false;
    }
  }

  // Fetches k's slot into the cache ahead of an insert or contains (a table bigger than
  // the cache costs one miss per lookup; a scan that knows its next keys hides it).
  void prefetch(std::uint64_t k) const {
    if (!slots_.empty()) __builtin_prefetch(&slots_[slot(k)]);
  }

  std::size_t size() const { return size_; }

 private:
  std::size_t slot(std::uint64_t k) const {
    // Fibonacci hashing: the top bits of k * 2^64/phi, which spread keys that differ in
    // their low bits only (consecutive vertex ids) over the whole table.
    return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ull) >> shift_);
  }

  void grow() {
    std::vector<std::uint64_t> old;
    old.swap(slots_);
    const int bits = old.empty() ? 10 : 64 - shift_ + 1;  // double: 5/16 full after
    slots_.assign(std::size_t{1} << bits, kEmpty);
    mask_ = slots_.size() - 1;
    shift_ = 64 - bits;
    size_ = 0;
    for (const std::uint64_t k : old)
      if (k != kEmpty) insert(k);
  }

  std::vector<std::uint64_t> slots_;
  std::size_t mask_ = 0;
  int shift_ = 64;
  std::size_t size_ = 0;
};

}  // namespace uvmesh::m2d::detail
