// KeySet64 (mesher2d/src/key_set.h) against std::unordered_set on keys built like the
// refinement's edge keys (a << 32 | b), on consecutive keys, and on keys that differ only
// in their high bits, across several table growths.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <random>
#include <unordered_set>

#include "mesher2d/src/key_set.h"

using uvmesh::m2d::detail::KeySet64;

namespace {
void same_as_reference(const std::vector<std::uint64_t>& keys) {
  KeySet64 s;
  std::unordered_set<std::uint64_t> ref;
  for (const std::uint64_t k : keys) {
    REQUIRE(s.insert(k) == ref.insert(k).second);
    REQUIRE(s.contains(k));
  }
  CHECK(s.size() == ref.size());
  for (const std::uint64_t k : keys) CHECK(s.contains(k));
  for (const std::uint64_t k : ref) CHECK_FALSE(s.insert(k));
}
}  // namespace

TEST_CASE("key_set: edge keys from random vertex pairs, with repeats", "[mesher2d][key_set]") {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::uint32_t> v(0, 20000);
  std::vector<std::uint64_t> keys;
  for (int i = 0; i < 200000; ++i) {
    const std::uint32_t a = v(rng), b = v(rng);
    keys.push_back(std::uint64_t{std::min(a, b)} << 32 | std::max(a, b));
  }
  same_as_reference(keys);
}

TEST_CASE("key_set: consecutive keys and keys differing only in their high bits",
          "[mesher2d][key_set]") {
  std::vector<std::uint64_t> keys;
  for (std::uint64_t i = 0; i < 50000; ++i) keys.push_back(i);
  for (std::uint64_t i = 0; i < 50000; ++i) keys.push_back(i << 32);
  for (std::uint64_t i = 0; i < 1000; ++i) keys.push_back(~std::uint64_t{0} - 1 - i);
  same_as_reference(keys);
}

TEST_CASE("key_set: empty set", "[mesher2d][key_set]") {
  KeySet64 s;
  CHECK(s.size() == 0);
  CHECK_FALSE(s.contains(0));
  CHECK(s.insert(0));
  CHECK(s.contains(0));
  CHECK_FALSE(s.contains(1));
}
