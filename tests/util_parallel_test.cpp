// parallel_chunks and parallel_pair: every chunk exactly once, on started threads (the caller
// waits), and the exception of the lowest failing chunk (of the first of a pair) rethrown.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

#include "util/parallel.hpp"

namespace fracref {
namespace {

TEST(UtilParallel, EveryChunkOnceOnStartedThreads) {
  const std::size_t n = 1000, chunks = chunk_count(n, 16);
  std::vector<std::atomic<int>> seen(n);
  std::atomic<int> on_caller{0};
  const std::thread::id caller = std::this_thread::get_id();
  parallel_chunks(n, chunks, 2, [&](std::size_t, std::size_t begin, std::size_t end) {
    if (std::this_thread::get_id() == caller) ++on_caller;
    for (std::size_t i = begin; i < end; ++i) ++seen[i];
  });
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(seen[i].load(), 1) << i;
  EXPECT_EQ(on_caller.load(), 0);
  // One thread: the caller does it all, in chunk order.
  std::vector<std::size_t> order;
  parallel_chunks(n, chunks, 1, [&](std::size_t c, std::size_t, std::size_t) { order.push_back(c); });
  ASSERT_EQ(order.size(), chunks);
  for (std::size_t c = 0; c < chunks; ++c) EXPECT_EQ(order[c], c);
}

TEST(UtilParallel, LowestFailingChunkAndFirstOfAPairAreRethrown) {
  try {
    parallel_chunks(100, 10, 2, [](std::size_t c, std::size_t, std::size_t) {
      if (c == 3 || c == 7) throw std::runtime_error("chunk " + std::to_string(c));
    });
    ADD_FAILURE() << "nothing thrown";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "chunk 3");
  }
  std::atomic<int> ran{0};
  try {
    parallel_pair([&] { ++ran; throw std::runtime_error("first"); }, [&] { ++ran; throw std::runtime_error("second"); });
    ADD_FAILURE() << "nothing thrown";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "first");
  }
  EXPECT_EQ(ran.load(), 2);
  int a = 0, b = 0;
  parallel_pair([&] { a = 1; }, [&] { b = 2; });
  EXPECT_EQ(a + b, 3);
}

}  // namespace
}  // namespace fracref
