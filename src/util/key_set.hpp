#pragma once
// A set of nonzero 64-bit keys with a known most size: open addressing on one flat array, for
// membership tests in hot serial loops (std::unordered_set allocates a node per key).
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace fracref {

class KeySet {
 public:
  /// Room for up to `most` keys (the table is at least twice that, so probes stay short).
  explicit KeySet(std::size_t most) : slots_(std::bit_ceil(2 * most + 2), 0) {}

  /// \pre key != 0 (0 marks an empty slot).
  bool contains(std::uint64_t key) const {
    for (std::size_t i = slot(key);; i = (i + 1) & (slots_.size() - 1)) {
      if (slots_[i] == key) return true;
      if (slots_[i] == 0) return false;
    }
  }

  /// \pre key != 0, and fewer than `most` distinct keys inserted before.
  void insert(std::uint64_t key) {
    std::size_t i = slot(key);
    while (slots_[i] != 0 && slots_[i] != key) i = (i + 1) & (slots_.size() - 1);
    slots_[i] = key;
  }

 private:
  std::size_t slot(std::uint64_t key) const { return std::size_t((key * 0x9E3779B97F4A7C15ull) >> 17) & (slots_.size() - 1); }
  std::vector<std::uint64_t> slots_;
};

}  // namespace fracref
