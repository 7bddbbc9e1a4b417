#pragma once
// Run fixed chunks of an index range on a few threads (shared by the rooms that split work:
// geom, refine, animate). Chunk boundaries depend only on n, so per-chunk results concatenated
// in chunk order are the same for any thread count.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>

namespace fracref {

/// The worker threads a call uses when its options name none: set_default_threads's value, or
/// else every hardware thread of the machine (at least 1). Results never depend on it.
int default_threads();

/// Sets what default_threads() returns from now on (the CLI's --threads); 0 = every hardware
/// thread. \pre n >= 0.
void set_default_threads(int n);

/// Number of chunks used for n items: enough for load balance, few enough to be cheap.
inline std::size_t chunk_count(std::size_t n, std::size_t min_chunk = 256) {
  return std::max<std::size_t>(1, std::min<std::size_t>(64, n / min_chunk));
}

namespace parallel_detail {

/// Runs work(context) once on each of `workers` threads kept for the purpose, side by side, and
/// returns when all have finished; the caller waits. Returns false without running anything when
/// the kept threads are busy with another caller's work or the caller is one of them (a nested
/// call): the caller then starts threads of its own.
/// \pre workers >= 1; work does not throw.
bool run_on_pool(int workers, void (*work)(void*), void* context);

}  // namespace parallel_detail

/// Calls fn(chunk, begin, end) for every chunk of [0, n) split into `chunks` contiguous parts,
/// on up to `threads` threads other than the caller's (kept between calls, or started for a
/// nested or concurrent call); the caller waits. Rethrows the exception of the lowest failing
/// chunk.
template <class Fn>
void parallel_chunks(std::size_t n, std::size_t chunks, int threads, Fn&& fn) {
  auto bounds = [&](std::size_t c) { return n * c / chunks; };
  const int workers = static_cast<int>(std::min<std::size_t>(std::max(threads, 1), chunks));
  if (workers <= 1) {
    for (std::size_t c = 0; c < chunks; ++c) fn(c, bounds(c), bounds(c + 1));
    return;
  }
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> errors(chunks);
  auto work = [&]() {
    for (std::size_t c = next++; c < chunks; c = next++) {
      try {
        fn(c, bounds(c), bounds(c + 1));
      } catch (...) {
        errors[c] = std::current_exception();
      }
    }
  };
  // The caller waits rather than works: on a machine with as many cores as chunks, a worker
  // started beside a busy caller can share the caller's core for the whole call, so the call
  // takes as long as two chunks in turn; beside a waiting caller it gets a core of its own.
  // Threads are kept between calls: waking a kept thread costs less than starting and joining a
  // new one, and the refiner makes many short calls. Threads that cannot be started leave their
  // chunks to the caller, so every chunk still runs.
  if (!parallel_detail::run_on_pool(workers, [](void* w) { (*static_cast<decltype(work)*>(w))(); }, &work)) {
    std::vector<std::thread> pool;
    try {
      for (int w = 0; w < workers; ++w) pool.emplace_back(work);
    } catch (const std::system_error&) {
    }
    for (auto& t : pool) t.join();
    if (pool.size() < std::size_t(workers)) work();
  }
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

/// Runs first() and second() side by side on two threads (the caller waits, as above).
/// Rethrows first's exception before second's, as running them in turn would.
template <class First, class Second>
void parallel_pair(First&& first, Second&& second) {
  parallel_chunks(2, 2, 2, [&](std::size_t part, std::size_t, std::size_t) { part == 0 ? first() : second(); });
}

}  // namespace fracref
