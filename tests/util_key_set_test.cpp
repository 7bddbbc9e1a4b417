// KeySet against std::set: the same membership answers for keys that collide in the table.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "util/key_set.hpp"

namespace fracref {
namespace {

TEST(KeySet, AnswersAsAnOrderedSet) {
  std::mt19937_64 rng(3);
  // Keys shaped as the flips' diagonals (small id << 32 | larger id), from few vertices so that
  // many repeat, and a table filled to its stated room.
  std::uniform_int_distribution<std::uint32_t> vertex(0, 300);
  KeySet set(2000);
  std::set<std::uint64_t> want;
  while (want.size() < 2000) {
    std::uint32_t a = vertex(rng), b = vertex(rng);
    if (a == b) continue;
    if (a > b) std::swap(a, b);
    const std::uint64_t key = (std::uint64_t(a) << 32) | b;
    EXPECT_EQ(set.contains(key), want.count(key) == 1);
    set.insert(key);
    want.insert(key);
    EXPECT_TRUE(set.contains(key));
  }
  for (std::uint32_t a = 0; a <= 300; ++a)
    for (std::uint32_t b = a + 1; b <= 300; ++b) {
      const std::uint64_t key = (std::uint64_t(a) << 32) | b;
      ASSERT_EQ(set.contains(key), want.count(key) == 1) << a << " " << b;
    }
}

}  // namespace
}  // namespace fracref
