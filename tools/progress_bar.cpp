// The progress bar on stderr (progress_bar.hpp).
#include "progress_bar.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace surftrace::tools {

ProgressBar::ProgressBar(bool enabled, std::string label)
    : enabled_(enabled && isatty(STDERR_FILENO)), label_(std::move(label)) {}

namespace {
// The terminal's width in columns (80 when it does not say).
std::size_t terminalColumns() {
  winsize size{};
  if (ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
  return 80;
}
}  // namespace

void ProgressBar::draw(const std::string& before, double fraction, const std::string& after) {
  // The bar shrinks first, then the text is cut, so that the line never wraps: a wrapped
  // line cannot be redrawn in place.
  const std::size_t columns = terminalColumns() - 1;
  std::string line = before;
  const std::size_t fixed = before.size() + after.size() + 3;  // " [" and "]"
  const std::size_t width = columns > fixed ? std::min<std::size_t>(25, columns - fixed) : 0;
  if (width >= 5) {
    const auto filled = static_cast<std::size_t>(std::clamp(fraction, 0.0, 1.0) * static_cast<double>(width));
    line += " [" + std::string(filled, '#') + std::string(width - filled, ' ') + "]";
  }
  line += after;
  if (line.size() > columns) line.resize(columns);
  std::fprintf(stderr, "\r%s\033[K", line.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::clear() {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  if (!drawn_) return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  drawn_ = false;
}

void ProgressBar::update(double fraction) {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  const int percent = static_cast<int>(100.0 * fraction);
  if (percent <= last_) return;
  last_ = percent;
  char after[32];
  std::snprintf(after, sizeof after, " %3d%%", percent);
  draw(label_, fraction, after);
  if (percent >= 100) std::fprintf(stderr, "\n"), drawn_ = false;
}

void ProgressBar::items(std::size_t done, std::size_t total, const char* unit) {
  if (!enabled_ || total == 0) return;
  std::lock_guard lock(mutex_);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = seconds > 0.0 ? static_cast<double>(done) / seconds : 0.0;
  const double left = rate > 0.0 ? static_cast<double>(total - done) / rate : 0.0;
  char after[160];
  std::snprintf(after, sizeof after, " %zu/%zu %s, %.1f %s/s, ETA %02d:%02d", done, total, unit, rate, unit,
                static_cast<int>(left) / 60, static_cast<int>(left) % 60);
  draw(label_, static_cast<double>(done) / static_cast<double>(total), after);
  if (done >= total) std::fprintf(stderr, "\n"), drawn_ = false;
}

}  // namespace surftrace::tools
