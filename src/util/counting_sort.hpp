#pragma once
// A stable counting sort whose counting and placing are split among a few threads (the box
// trees' radix sort, the fracture surface's vertex-face lists and edge table).
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "util/parallel.hpp"

namespace fracref {

/// Sorts by key (< nkeys) the items that the sources 0 .. n-1 produce: `keys(src, emit)` calls
/// emit(key, item) for each of src's items, in order; `place(src, item, pos)` puts that item at
/// position `pos`. The sources are split into `parts` contiguous ranges that count and place side
/// by side, each range's items after those of the ranges before it within every key, so items of
/// one key come out in source order (then item order) for any number of parts.
/// \return the keys' offsets (size nkeys + 1).
/// \pre parts >= 1, fewer than 2^32 items.
template <class Keys, class Place>
std::vector<std::uint32_t> counting_sort(std::size_t n, std::size_t nkeys, std::size_t parts, const Keys& keys,
                                         const Place& place) {
  std::vector<std::vector<std::uint32_t>> cursor(parts, std::vector<std::uint32_t>(nkeys, 0));
  parallel_chunks(n, parts, int(parts), [&](std::size_t p, std::size_t begin, std::size_t end) {
    for (std::size_t src = begin; src < end; ++src) keys(src, [&](std::size_t key, std::uint32_t) { ++cursor[p][key]; });
  });
  std::vector<std::uint32_t> offsets(nkeys + 1, 0);
  for (std::size_t key = 0; key < nkeys; ++key) {
    std::uint32_t at = offsets[key];
    for (auto& c : cursor) at += std::exchange(c[key], at);
    offsets[key + 1] = at;
  }
  parallel_chunks(n, parts, int(parts), [&](std::size_t p, std::size_t begin, std::size_t end) {
    for (std::size_t src = begin; src < end; ++src)
      keys(src, [&](std::size_t key, std::uint32_t item) { place(src, item, cursor[p][key]++); });
  });
  return offsets;
}

}  // namespace fracref
