// SPDX-License-Identifier: BSL-1.0
// progress.hpp's progress line and bar, compiled once into perch_support.
#include "support/progress.hpp"

namespace perch::support {

namespace detail {

/// "m:ss", or "h:mm:ss" from one hour on (seconds rounded down; negative/NaN → 0).
std::string format_duration(double seconds) {
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

std::string format_progress_line(std::size_t done, std::size_t total, double elapsed_s, int width) {
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

progress_bar::progress_bar(std::size_t total, const progress_options& options)
    : total_(total), options_(options), start_(clock::now()) {
  if (options_.stream == nullptr) options_.display = progress_display::off;
  if (options_.display == progress_display::automatic)
    options_.display =
        is_terminal(options_.stream) ? progress_display::terminal : progress_display::plain;
  if (options_.width <= 0) options_.width = default_width();
}

void progress_bar::tick(std::size_t n) {
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

void progress_bar::finish() {
  std::lock_guard lock(mutex_);
  if (finished_) return;
  finished_ = true;
  if (options_.display == progress_display::off) return;
  draw_locked(since_start_ns(), true);
}

bool progress_bar::is_terminal(std::FILE* stream) noexcept {
  if (stream == nullptr) return false;
#if defined(_WIN32)
  return _isatty(_fileno(stream)) != 0;
#else
  return isatty(fileno(stream)) != 0;
#endif
}

int progress_bar::default_width() const noexcept {
#if !defined(_WIN32)
  if (options_.display == progress_display::terminal) {
    winsize size{};
    if (ioctl(fileno(options_.stream), TIOCGWINSZ, &size) == 0 && size.ws_col > 1)
      return static_cast<int>(size.ws_col) - 1;
  }
#endif
  return 79;
}

void progress_bar::draw_locked(std::int64_t now_ns, bool final_line) {
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

}  // namespace perch::support
