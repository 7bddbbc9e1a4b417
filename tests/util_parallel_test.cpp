// parallel_chunks and parallel_pair: every chunk exactly once, on threads other than the
// caller's (the caller waits), also for nested and concurrent calls, and the exception of the
// lowest failing chunk (of the first of a pair) rethrown.
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

// A call made from inside a chunk (the kept threads are busy with the outer call) and calls
// from several threads at once each run every chunk once, none on its caller.
TEST(UtilParallel, NestedAndConcurrentCallsRunEveryChunkOnce) {
  const std::size_t n = 64, inner = 200;
  std::vector<std::atomic<int>> seen(n * inner);
  std::atomic<int> on_caller{0};
  parallel_chunks(n, n, 2, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const std::thread::id outer = std::this_thread::get_id();
      parallel_chunks(inner, chunk_count(inner, 16), 2, [&](std::size_t, std::size_t b, std::size_t e) {
        if (std::this_thread::get_id() == outer) ++on_caller;
        for (std::size_t k = b; k < e; ++k) ++seen[i * inner + k];
      });
    }
  });
  for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i].load(), 1) << i;
  EXPECT_EQ(on_caller.load(), 0);
  std::vector<std::atomic<int>> total(4);
  std::vector<std::thread> callers;
  for (int t = 0; t < 4; ++t)
    callers.emplace_back([&, t] {
      for (int round = 0; round < 50; ++round)
        parallel_chunks(1000, 10, 2, [&](std::size_t, std::size_t b, std::size_t e) { total[t] += int(e - b); });
    });
  for (std::thread& c : callers) c.join();
  for (int t = 0; t < 4; ++t) EXPECT_EQ(total[t].load(), 50 * 1000) << t;
  // More threads than the kept ones so far: the pool grows, every chunk still once.
  std::vector<std::atomic<int>> wide(100);
  parallel_chunks(100, 100, 5, [&](std::size_t, std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) ++wide[k];
  });
  for (std::size_t k = 0; k < wide.size(); ++k) EXPECT_EQ(wide[k].load(), 1) << k;
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
