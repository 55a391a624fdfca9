// SPDX-License-Identifier: BSL-1.0
// Tests for support/progress.hpp and support/parallel_for.hpp (the pieces of `perch batch`).
#include "support/progress.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "support/parallel_for.hpp"

using perch::support::format_progress_line;

namespace {

std::string read_all(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string out;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) out.append(buffer, n);
  std::fseek(f, 0, SEEK_END);  // C stdio needs a seek between reading and writing
  return out;
}

}  // namespace

TEST_CASE("format_progress_line: counts, percentage, rate, ETA and bar") {
  CHECK(format_progress_line(45, 100, 3.66, 0) == " 45/100   45%  12.3/s  ETA 0:04");
  CHECK(format_progress_line(45, 100, 3.66, 56) ==
        "[#########-------------]  45/100   45%  12.3/s  ETA 0:04");
  CHECK(format_progress_line(45, 100, 3.66, 56).size() == 56);
  CHECK(format_progress_line(0, 100, 0.0, 0) == "  0/100    0%  --/s  ETA --:--");
  CHECK(format_progress_line(0, 100, 5.0, 0) == "  0/100    0%  0.0/s  ETA --:--");
  CHECK(format_progress_line(100, 100, 125.0, 0) == "100/100  100%  0.8/s  in 2:05");
  CHECK(format_progress_line(150, 100, 10.0, 0) == "100/100  100%  10.0/s  in 0:10");
  CHECK(format_progress_line(99, 100, 1.0, 0) == " 99/100   99%  99.0/s  ETA 0:00");
  CHECK(format_progress_line(1, 10000, 4000.0, 0) == "    1/10000    0%  0.0/s  ETA 11110:00:00");
  CHECK(format_progress_line(5000, 20000, 2.0, 0) == " 5000/20000   25%  2500/s  ETA 0:06");
  CHECK(format_progress_line(0, 0, 0.0, 0) == "0/0  100%  --/s  in 0:00");
  // The bar is left out when there is no room for 5 cells, and never cuts the numbers.
  const std::string text = format_progress_line(1, 2, 1.0, 0);
  CHECK(format_progress_line(1, 2, 1.0, static_cast<int>(text.size()) + 7) == text);
  CHECK(format_progress_line(1, 2, 1.0, static_cast<int>(text.size()) + 8) ==
        "[##---] " + text);
  CHECK(format_progress_line(1, 2, 1.0, 3) == text);
  // Odd elapsed times.
  CHECK(format_progress_line(1, 2, -1.0, 0) == "1/2   50%  --/s  ETA --:--");
  CHECK(format_progress_line(1, 2, 1e300, 0) == "1/2   50%  0.0/s  ETA 99999:59:59");
  // Deterministic.
  CHECK(format_progress_line(7, 9, 1.5, 70) == format_progress_line(7, 9, 1.5, 70));
}

TEST_CASE("progress_bar: plain lines from many threads, one final line with a newline") {
  std::FILE* f = std::tmpfile();
  REQUIRE(f != nullptr);
  {
    perch::support::progress_bar bar(1000, {.stream = f,
                                            .display = perch::support::progress_display::plain,
                                            .width = 60});
    CHECK(bar.display() == perch::support::progress_display::plain);
    perch::support::parallel_for(1000, 4, [&](std::size_t) { bar.tick(); });
    CHECK(bar.done() == 1000);
  }  // the destructor finishes
  const std::string out = read_all(f);
  std::fclose(f);
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < out.size()) {
    const std::size_t end = out.find('\n', start);
    REQUIRE(end != std::string::npos);  // every line ends with a newline
    lines.push_back(out.substr(start, end - start));
    start = end + 1;
  }
  REQUIRE(!lines.empty());
  CHECK(lines.size() <= 11);
  CHECK(lines.back().find("1000/1000  100%") != std::string::npos);
  CHECK(lines.back().find(" in ") != std::string::npos);
  CHECK(out.find('\r') == std::string::npos);
  for (const std::string& l : lines) CHECK(l.size() <= 60);
  std::size_t hundreds = 0;
  for (const std::string& l : lines) if (l.find("100%") != std::string::npos) ++hundreds;
  CHECK(hundreds == 1);
}

TEST_CASE("progress_bar: terminal mode redraws in place, at most ~10 times a second") {
  std::FILE* f = std::tmpfile();
  REQUIRE(f != nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  {
    perch::support::progress_bar bar(
        200, {.stream = f, .display = perch::support::progress_display::terminal, .width = 50});
    for (int i = 0; i < 200; ++i) {
      bar.tick();
      std::this_thread::sleep_for(std::chrono::microseconds(1500));
    }
    bar.finish();
    bar.finish();  // once only
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string out = read_all(f);
  std::fclose(f);
  const auto redraws = static_cast<double>(std::count(out.begin(), out.end(), '\r'));
  CHECK(redraws >= 2);
  CHECK(redraws <= seconds * 10.0 + 2.0);
  CHECK(std::count(out.begin(), out.end(), '\n') == 1);
  CHECK(out.back() == '\n');
  CHECK(out.find("200/200  100%") != std::string::npos);
}

TEST_CASE("progress_bar: off writes nothing; a null stream is off; not a terminal is plain") {
  std::FILE* f = std::tmpfile();
  REQUIRE(f != nullptr);
  {
    perch::support::progress_bar bar(3, {.stream = f, .display = perch::support::progress_display::off});
    bar.tick(3);
  }
  {
    perch::support::progress_bar bar(3, {.stream = nullptr});
    CHECK(bar.display() == perch::support::progress_display::off);
    bar.tick();
  }
  CHECK(read_all(f).empty());
  CHECK_FALSE(perch::support::progress_bar::is_terminal(f));
  {
    perch::support::progress_bar automatic(1, {.stream = f});
    CHECK(automatic.display() == perch::support::progress_display::plain);
    automatic.tick();
  }
  const std::string out = read_all(f);
  CHECK(out.find("1/1  100%") != std::string::npos);
  CHECK(std::count(out.begin(), out.end(), '\n') == 1);
  std::fclose(f);
}

TEST_CASE("parallel_for: every index exactly once, any number of jobs") {
  for (unsigned jobs : {0u, 1u, 2u, 3u, 8u, 64u}) {
    for (std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{5}, std::size_t{1000}}) {
      std::vector<std::atomic<int>> hits(count);
      perch::support::parallel_for(count, jobs, [&](std::size_t i) {
        hits[i].fetch_add(1, std::memory_order_relaxed);
      });
      for (const auto& h : hits) CHECK(h.load() == 1);
    }
  }
  CHECK(perch::support::worker_count(100, 0) == perch::support::default_job_count());
  CHECK(perch::support::worker_count(3, 8) == 3);
  CHECK(perch::support::worker_count(0, 8) == 1);
  CHECK(perch::support::worker_count(10, 4) == 4);
  CHECK(perch::support::default_job_count() >= 1);
}

TEST_CASE("parallel_for: worker ids index per-worker scratch; one job runs on the caller") {
  const unsigned workers = perch::support::worker_count(500, 4);
  std::vector<std::size_t> per_worker(workers, 0);  // each worker writes only its own slot
  std::vector<std::thread::id> ids(workers);
  perch::support::parallel_for(500, 4, [&](std::size_t, unsigned worker) {
    REQUIRE(worker < workers);
    ++per_worker[worker];
    ids[worker] = std::this_thread::get_id();
  });
  std::size_t total = 0;
  for (std::size_t n : per_worker) total += n;
  CHECK(total == 500);
  std::thread::id seen;
  perch::support::parallel_for(10, 1, [&](std::size_t) { seen = std::this_thread::get_id(); });
  CHECK(seen == std::this_thread::get_id());
}

TEST_CASE("parallel_map: results by index, independent of threads and timing") {
  const auto square = [](std::size_t i) {
    // Uneven work so threads finish out of order.
    if (i % 7 == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));
    return std::to_string(i * i);
  };
  const auto one = perch::support::parallel_map(300, 1, square);
  const auto many = perch::support::parallel_map(300, 6, square);
  REQUIRE(one.size() == 300);
  CHECK(one == many);
  CHECK(many[17] == "289");
  const auto with_worker = perch::support::parallel_map(
      50, 3, [](std::size_t i, unsigned worker) { return static_cast<int>(i) + 0 * static_cast<int>(worker); });
  for (std::size_t i = 0; i < with_worker.size(); ++i) CHECK(with_worker[i] == static_cast<int>(i));
  CHECK(perch::support::parallel_map(0, 4, square).empty());
}
