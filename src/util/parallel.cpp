#include "util/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace fracref {
namespace parallel_detail {
namespace {

thread_local bool t_on_pool = false;

// Threads kept between calls, all woken by each call: only the first `wanted` to wake take a
// part. A call's parts are done when it returns, so a thread that sleeps through one generation
// cannot owe it a part.
class Pool {
 public:
  ~Pool() {
    {
      std::lock_guard<std::mutex> lock(m_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
  }

  bool run(int workers, void (*work)(void*), void* context) {
    if (t_on_pool) return false;
    std::unique_lock<std::mutex> busy(run_, std::try_to_lock);
    if (!busy.owns_lock()) return false;
    std::unique_lock<std::mutex> lock(m_);
    try {
      while (threads_.size() < std::size_t(workers)) threads_.emplace_back([this] { loop(); });
    } catch (const std::system_error&) {
      return false;  // the caller starts what it can, and does the rest itself
    }
    work_ = work, context_ = context;
    wanted_ = workers, taken_ = 0, pending_ = workers;
    ++generation_;
    wake_.notify_all();
    done_.wait(lock, [&] { return pending_ == 0; });
    return true;
  }

 private:
  void loop() {
    t_on_pool = true;
    std::uint64_t seen = 0;  // below every generation: a thread started for a call takes part in it
    std::unique_lock<std::mutex> lock(m_);
    for (;;) {
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      if (taken_ == wanted_) continue;
      ++taken_;
      void (*work)(void*) = work_;
      void* context = context_;
      lock.unlock();
      work(context);
      lock.lock();
      if (--pending_ == 0) done_.notify_one();
    }
  }

  std::mutex run_;  // one call at a time
  std::mutex m_;
  std::condition_variable wake_, done_;
  std::vector<std::thread> threads_;
  std::uint64_t generation_ = 0;
  void (*work_)(void*) = nullptr;
  void* context_ = nullptr;
  int wanted_ = 0, taken_ = 0, pending_ = 0;
  bool stop_ = false;
};

}  // namespace

bool run_on_pool(int workers, void (*work)(void*), void* context) {
  static Pool pool;
  return pool.run(workers, work, context);
}

}  // namespace parallel_detail
namespace {
std::atomic<int> g_default_threads{0};
}

int default_threads() {
  const int n = g_default_threads.load(std::memory_order_relaxed);
  if (n > 0) return n;
  return std::max(1, int(std::thread::hardware_concurrency()));
}

void set_default_threads(int n) { g_default_threads.store(std::max(0, n), std::memory_order_relaxed); }

}  // namespace fracref
