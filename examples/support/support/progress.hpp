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

namespace detail {

/// "m:ss", or "h:mm:ss" from one hour on (seconds rounded down; negative/NaN → 0).
inline std::string format_duration(double seconds) {
  if (!(seconds > 0.0)) seconds = 0.0;
  seconds = std::min(seconds, 359999999.0);  // < 100000 hours keeps the text bounded
  const auto total = static_cast<long long>(seconds);
  const long long h = total / 3600;
  const long long m = (total / 60) % 60;
  const long long s = total % 60;
  char buffer[48];
  if (h > 0)
    std::snprintf(buffer, sizeof buffer, "%lld:%02lld:%02lld", h, m, s);
  else
    std::snprintf(buffer, sizeof buffer, "%lld:%02lld", m, s);
  return buffer;
}

}  // namespace detail

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
[[nodiscard]] inline std::string format_progress_line(std::size_t done, std::size_t total,
                                                      double elapsed_s, int width) {
  done = std::min(done, total);
  const bool finished = done >= total;
  const double fraction =
      total == 0 ? 1.0 : static_cast<double>(done) / static_cast<double>(total);
  const unsigned percent =
      total == 0 ? 100u
                 : static_cast<unsigned>((static_cast<unsigned long long>(done) * 100ull) /
                                         static_cast<unsigned long long>(total));
  const bool timed = elapsed_s > 0.0 && std::isfinite(elapsed_s);
  const double rate = timed ? static_cast<double>(done) / elapsed_s : 0.0;

  char rate_text[32];
  if (!timed)
    std::snprintf(rate_text, sizeof rate_text, "--/s");
  else if (rate < 100.0)
    std::snprintf(rate_text, sizeof rate_text, "%.1f/s", rate);
  else
    std::snprintf(rate_text, sizeof rate_text, "%.0f/s", std::min(rate, 1e15));

  std::string eta;
  if (finished)
    eta = "in " + detail::format_duration(timed ? elapsed_s : 0.0);
  else if (done == 0 || !(rate > 0.0))
    eta = "ETA --:--";
  else
    eta = "ETA " + detail::format_duration(static_cast<double>(total - done) / rate);

  const std::string total_text = std::to_string(total);
  std::string done_text = std::to_string(done);
  if (done_text.size() < total_text.size())
    done_text.insert(0, total_text.size() - done_text.size(), ' ');
  char percent_text[8];
  std::snprintf(percent_text, sizeof percent_text, "%3u%%", percent);

  std::string text = done_text + "/" + total_text + "  " + percent_text + "  " + rate_text +
                     "  " + eta;
  const long long cells = static_cast<long long>(width) - static_cast<long long>(text.size()) - 3;
  if (cells < 5) return text;
  const auto filled = static_cast<long long>(std::floor(fraction * static_cast<double>(cells)));
  std::string line = "[";
  line.append(static_cast<std::size_t>(filled), '#');
  line.append(static_cast<std::size_t>(cells - filled), '-');
  line += "] ";
  line += text;
  return line;
}

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
  explicit progress_bar(std::size_t total, const progress_options& options = {})
      : total_(total), options_(options), start_(clock::now()) {
    if (options_.stream == nullptr) options_.display = progress_display::off;
    if (options_.display == progress_display::automatic)
      options_.display =
          is_terminal(options_.stream) ? progress_display::terminal : progress_display::plain;
    if (options_.width <= 0) options_.width = default_width();
  }
  progress_bar(const progress_bar&) = delete;
  progress_bar& operator=(const progress_bar&) = delete;
  /// Calls `finish()`.
  ~progress_bar() { finish(); }

  /// Records `n` more finished items; redraws if due. Thread-safe, never blocks on the
  /// output (a thread that finds another one drawing just carries on).
  void tick(std::size_t n = 1) {
    const std::size_t done = done_.fetch_add(n, std::memory_order_relaxed) + n;
    if (options_.display == progress_display::off) return;
    const std::int64_t now = since_start_ns();
    if (options_.display == progress_display::terminal) {
      const auto interval = static_cast<std::int64_t>(options_.min_interval_s * 1e9);
      if (now - last_draw_ns_.load(std::memory_order_relaxed) < interval) return;
    } else {
      // The finished line is left to finish(), so a log never shows 100% twice.
      if (done >= total_ || tenth(done) <= last_tenth_.load(std::memory_order_relaxed)) return;
    }
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock() || finished_) return;
    draw_locked(now, false);
  }

  /// Writes the final line and a newline (once; later calls do nothing). Thread-safe.
  void finish() {
    std::lock_guard lock(mutex_);
    if (finished_) return;
    finished_ = true;
    if (options_.display == progress_display::off) return;
    draw_locked(since_start_ns(), true);
  }

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
  [[nodiscard]] static bool is_terminal(std::FILE* stream) noexcept {
    if (stream == nullptr) return false;
#if defined(_WIN32)
    return _isatty(_fileno(stream)) != 0;
#else
    return isatty(fileno(stream)) != 0;
#endif
  }

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

  [[nodiscard]] int default_width() const noexcept {
#if !defined(_WIN32)
    if (options_.display == progress_display::terminal) {
      winsize size{};
      if (ioctl(fileno(options_.stream), TIOCGWINSZ, &size) == 0 && size.ws_col > 1)
        return static_cast<int>(size.ws_col) - 1;
    }
#endif
    return 79;
  }

  void draw_locked(std::int64_t now_ns, bool final_line) {
    const std::size_t done = done_.load(std::memory_order_relaxed);
    last_draw_ns_.store(now_ns, std::memory_order_relaxed);
    last_tenth_.store(tenth(done), std::memory_order_relaxed);
    const std::string line =
        format_progress_line(done, total_, static_cast<double>(now_ns) * 1e-9, options_.width);
    std::string out;
    if (options_.display == progress_display::terminal) {
      out = "\r" + line;
      if (line.size() < drawn_length_) out.append(drawn_length_ - line.size(), ' ');
      drawn_length_ = line.size();
      if (final_line) out += '\n';
    } else {
      out = line + "\n";
    }
    std::fputs(out.c_str(), options_.stream);
    std::fflush(options_.stream);
  }

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
