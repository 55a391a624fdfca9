// SPDX-License-Identifier: BSL-1.0
/// \file
/// A progress bar on stderr for `perch batch`: done/total, percentage, rate and ETA. Host
/// code, not part of the library.
///
/// On a terminal the line is redrawn in place ('\r') at most once per `min_interval_s`
/// (default 0.1 s, so ~10 updates a second). When the stream is not a terminal (a CI log, a
/// pipe) it writes plain lines instead: one each time another tenth of the work is done, so a
/// log gets at most ~11 lines. `finish()` (or the destructor) writes the final state and a
/// newline. `tick()` may be called from any number of threads at once.
///
/// The line itself comes from the pure function `format_progress_line`, so tests can check
/// it without a clock or a terminal.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>

#if defined(_WIN32)
#include <io.h>
#else
#include <sys/ioctl.h>
#include <unistd.h>
#endif

namespace perch::support {

/// The progress line for `done` of `total` items after `elapsed_s` seconds, at most `width`
/// characters when the numbers fit (the numbers are never cut; `width` ≤ 0 means no bar):
///
///     [#########-----------]  45/100  45%  12.3/s  ETA 0:04
///
///   - `done` is clamped to `total`; the percentage is rounded down, so 100% means finished;
///     `total` = 0 counts as finished.
///   - rate = done / elapsed items per second, one decimal below 100/s, `--/s` before any time
///     has passed.
///   - `ETA m:ss` (or `h:mm:ss`) = remaining / rate; `ETA --:--` while nothing is done; once
///     finished the field is `in m:ss`, the elapsed time.
///   - the bar `[###---]` takes the width left after the text and one space, and is left out
///     when fewer than 5 cells would be left.
/// Deterministic: the same numbers give the same string.
[[nodiscard]] std::string format_progress_line(std::size_t done, std::size_t total,
                                               double elapsed_s, int width);

/// Where `progress_bar` draws.
enum class progress_display : std::uint8_t {
  automatic,  ///< `terminal` if the stream is a terminal (isatty), else `plain`
  terminal,   ///< redraw one line in place with '\r', at most once per `min_interval_s`
  plain,      ///< a new line at every further tenth of the work, and the final one
  off,        ///< write nothing
};

/// How `progress_bar` draws.
struct progress_options {
  std::FILE* stream = stderr;                      ///< where to write (not owned)
  progress_display display = progress_display::automatic;
  int width = 0;                 ///< line width; 0 = the terminal's width − 1, or 79
  double min_interval_s = 0.1;   ///< least time between two terminal redraws
};

/// A thread-safe progress bar over `total` items (see the file comment).
class progress_bar {
 public:
  /// Starts the clock. Nothing is written until the first `tick` or `finish`.
  explicit progress_bar(std::size_t total, const progress_options& options = {});
  progress_bar(const progress_bar&) = delete;
  progress_bar& operator=(const progress_bar&) = delete;
  /// Calls `finish()`.
  ~progress_bar() { finish(); }

  /// Records `n` more finished items; redraws if due. Thread-safe, never blocks on the
  /// output (a thread that finds another one drawing just carries on).
  void tick(std::size_t n = 1);

  /// Writes the final line and a newline (once; later calls do nothing). Thread-safe.
  void finish();

  /// Items finished so far.
  [[nodiscard]] std::size_t done() const noexcept { return done_.load(std::memory_order_relaxed); }
  /// The total given to the constructor.
  [[nodiscard]] std::size_t total() const noexcept { return total_; }
  /// How the bar draws (never `automatic` after construction).
  [[nodiscard]] progress_display display() const noexcept { return options_.display; }
  /// Seconds since construction.
  [[nodiscard]] double elapsed_s() const noexcept {
    return static_cast<double>(since_start_ns()) * 1e-9;
  }

  /// True if `stream` is a terminal.
  [[nodiscard]] static bool is_terminal(std::FILE* stream) noexcept;

 private:
  using clock = std::chrono::steady_clock;

  [[nodiscard]] std::int64_t since_start_ns() const noexcept {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(clock::now() - start_).count();
  }

  [[nodiscard]] long long tenth(std::size_t done) const noexcept {
    if (total_ == 0) return 10;
    return static_cast<long long>(
        (static_cast<unsigned long long>(std::min(done, total_)) * 10ull) /
        static_cast<unsigned long long>(total_));
  }

  [[nodiscard]] int default_width() const noexcept;

  void draw_locked(std::int64_t now_ns, bool final_line);

  std::size_t total_;
  progress_options options_;
  clock::time_point start_;
  std::atomic<std::size_t> done_{0};
  std::atomic<std::int64_t> last_draw_ns_{-(std::int64_t{1} << 62)};
  std::atomic<long long> last_tenth_{-1};
  std::mutex mutex_;
  bool finished_ = false;
  std::size_t drawn_length_ = 0;
};

}  // namespace perch::support
