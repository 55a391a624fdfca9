// SPDX-License-Identifier: BSL-1.0
/// \file
/// `parallel_for` / `parallel_map`: run `count` independent jobs over a few threads (the perch
/// tool's `--jobs`). Host code, not part of the library.
///
/// Workers pull the next index from one atomic counter, so a slow job never holds up the
/// others, and results are stored by index, so the output order never depends on the threads
/// or the timing. The calling thread is one of the workers; with one worker (or one job)
/// everything runs on the calling thread and no thread is created.
///
/// Nothing here throws by itself; a job must not throw either (an exception escaping a
/// worker thread ends the program, as `std::thread` specifies). Thread creation failing
/// (`std::system_error`) is not caught: the tool behaves like the library and does not use
/// exceptions.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace perch::support {

/// The default worker count: `std::thread::hardware_concurrency()`, or 1 if unknown.
[[nodiscard]] inline unsigned default_job_count() noexcept {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : n;
}

/// The number of workers `parallel_for(count, jobs, ...)` uses: `jobs` (0 = `default_job_count()`)
/// but no more than `count`, and at least 1.
[[nodiscard]] inline unsigned worker_count(std::size_t count, unsigned jobs) noexcept {
  if (jobs == 0) jobs = default_job_count();
  if (count < jobs) jobs = static_cast<unsigned>(count);
  return jobs == 0 ? 1 : jobs;
}

/// Calls `body(i)` — or `body(i, worker)` if it takes two arguments, with `worker` in
/// [0, worker_count) identifying the calling worker, e.g. to index per-worker scratch such as
/// a `perch::workspace` — exactly once for every i in [0, count), over
/// `worker_count(count, jobs)` threads (the calling thread included). Returns when all jobs
/// are done. Jobs run in no particular order; each index is handed out once.
template <class Body>
void parallel_for(std::size_t count, unsigned jobs, Body&& body) {
  constexpr bool with_worker = std::is_invocable_v<Body&, std::size_t, unsigned>;
  static_assert(with_worker || std::is_invocable_v<Body&, std::size_t>,
                "parallel_for: body must be callable as body(index) or body(index, worker)");
  const unsigned workers = worker_count(count, jobs);
  std::atomic<std::size_t> next{0};
  auto run = [&](unsigned worker) {
    while (true) {
      const std::size_t i = next.fetch_add(1, std::memory_order_relaxed);
      if (i >= count) return;
      if constexpr (with_worker)
        body(i, worker);
      else
        body(i);
    }
  };
  if (workers <= 1) {
    run(0);
    return;
  }
  std::vector<std::thread> threads;
  threads.reserve(workers - 1);
  for (unsigned w = 1; w < workers; ++w) threads.emplace_back(run, w);
  run(0);
  for (std::thread& t : threads) t.join();
}

/// `parallel_for` collecting `fn(i)` (or `fn(i, worker)`) into a vector in index order:
/// result[i] = fn(i), whatever thread ran it. The result type must be default-constructible
/// and move-assignable.
template <class Fn>
[[nodiscard]] auto parallel_map(std::size_t count, unsigned jobs, Fn&& fn) {
  constexpr bool with_worker = std::is_invocable_v<Fn&, std::size_t, unsigned>;
  using result_type = std::decay_t<
      typename std::conditional_t<with_worker, std::invoke_result<Fn&, std::size_t, unsigned>,
                                  std::invoke_result<Fn&, std::size_t>>::type>;
  std::vector<result_type> results(count);
  parallel_for(count, jobs, [&](std::size_t i, unsigned worker) {
    if constexpr (with_worker)
      results[i] = fn(i, worker);
    else
      results[i] = fn(i);
  });
  return results;
}

}  // namespace perch::support
