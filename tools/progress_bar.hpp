// The progress bar that `area`, `render` and `trajectory` draw on stderr.
#pragma once

#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace surftrace::tools {

// A one-line progress bar on stderr, drawn only when stderr is a terminal, never wider than
// the terminal. Call clear() before printing anything else to the terminal (a row on
// stdout); the next update draws the bar again below it.
class ProgressBar {
 public:
  // `label` starts the line ("rendering", "frames").
  ProgressBar(bool enabled, std::string label);
  // A fraction of one piece of work.
  void update(double fraction);
  // `done` of `total` items, with items per second and the time left.
  void items(std::size_t done, std::size_t total, const char* unit);
  // Erases the bar's line, so that other output starts on a clean line.
  void clear();

 private:
  void draw(const std::string& before, double fraction, const std::string& after);

  bool enabled_;
  bool drawn_ = false;
  std::string label_;
  std::mutex mutex_;
  int last_ = -1;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace surftrace::tools
