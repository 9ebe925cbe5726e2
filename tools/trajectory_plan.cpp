// Frames, shards and output names of a trajectory run (trajectory_plan.hpp).
#include "trajectory_plan.hpp"

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <stdexcept>
#include <string_view>

namespace surftrace::tools {
namespace {

std::optional<std::size_t> count(std::string_view text) {
  std::size_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return v;
}

std::optional<std::string> environment(const char* name) {
  const char* v = std::getenv(name);
  if (!v) return std::nullopt;
  return std::string(v);
}

}  // namespace

std::vector<std::size_t> selectFrames(const std::string& text, std::size_t frameCount) {
  const auto fail = [&](const std::string& why) {
    throw std::invalid_argument("--frames '" + text + "': " + why +
                                " (expected a:b:step, frames a, a+step, ... below b, numbered from 0; e.g. 0:98:2)");
  };
  std::size_t first = 0, end = frameCount, step = 1;
  if (!text.empty()) {
    std::string_view parts[3];
    std::size_t n = 0, start = 0;
    for (std::size_t i = 0; i <= text.size(); ++i) {
      if (i < text.size() && text[i] != ':') continue;
      if (n == 3) fail("more than two colons");
      parts[n++] = std::string_view(text).substr(start, i - start);
      start = i + 1;
    }
    const auto field = [&](std::string_view part, const char* what) {
      const auto v = count(part);
      if (!v) fail(std::string(what) + " '" + std::string(part) + "' is not a whole number >= 0");
      return *v;
    };
    if (!parts[0].empty()) first = field(parts[0], "the first frame");
    if (n == 1) {
      end = first + 1;  // "k": frame k alone
    } else {
      if (!parts[1].empty()) end = std::min(field(parts[1], "the end"), frameCount);
      if (n == 3 && !parts[2].empty()) step = field(parts[2], "the step");
    }
    if (step == 0) fail("the step must be at least 1");
    if (first >= frameCount)
      fail("frame " + std::to_string(first) + " does not exist: the trajectory holds frames 0 to " +
           std::to_string(frameCount - 1));
  }
  std::vector<std::size_t> frames;
  for (std::size_t k = first; k < end; k += step) frames.push_back(k);
  if (frames.empty()) fail("selects no frame");
  return frames;
}

Shard chooseShard(const std::string& option, const std::optional<std::string>& taskId,
                  const std::optional<std::string>& taskCount, const std::optional<std::string>& taskMin) {
  Shard shard;
  if (!option.empty()) {
    const std::size_t slash = option.find('/');
    const auto i = count(std::string_view(option).substr(0, slash));
    const auto n = slash == std::string::npos ? std::nullopt : count(std::string_view(option).substr(slash + 1));
    if (!i || !n || *n == 0 || *i >= *n)
      throw std::invalid_argument("--shard '" + option +
                                  "': expected i/n with 0 <= i < n, e.g. 0/4 (this process renders the i-th, "
                                  "(i+n)-th, ... of the selected frames)");
    return {*i, *n, "--shard " + option};
  }
  if (!taskId && !taskCount) return shard;
  const auto need = [](const std::optional<std::string>& v, const char* name) {
    if (!v) throw std::invalid_argument(std::string(name) + " is not set, though the other Slurm array variable is");
    const auto n = count(*v);
    if (!n) throw std::invalid_argument(std::string(name) + "='" + *v + "' is not a whole number");
    return *n;
  };
  const std::size_t id = need(taskId, "SLURM_ARRAY_TASK_ID");
  const std::size_t n = need(taskCount, "SLURM_ARRAY_TASK_COUNT");
  const std::size_t min = taskMin ? need(taskMin, "SLURM_ARRAY_TASK_MIN") : 0;
  if (n == 0 || id < min || id - min >= n)
    throw std::invalid_argument("Slurm array task " + *taskId + " of " + *taskCount + " (first " + std::to_string(min) +
                                "): submit a contiguous array such as --array=0-" + std::to_string(n ? n - 1 : 3) +
                                ", or give --shard i/n");
  return {id - min, n, "Slurm array task " + *taskId + " of " + *taskCount};
}

Shard shardFromEnvironment(const std::string& option) {
  return chooseShard(option, environment("SLURM_ARRAY_TASK_ID"), environment("SLURM_ARRAY_TASK_COUNT"),
                     environment("SLURM_ARRAY_TASK_MIN"));
}

std::vector<std::size_t> framesOfShard(const std::vector<std::size_t>& selected, const Shard& shard) {
  std::vector<std::size_t> mine;
  for (std::size_t i = shard.index; i < selected.size(); i += shard.count) mine.push_back(selected[i]);
  return mine;
}

FramePattern::FramePattern(const std::string& option, const std::string& pattern) {
  const auto fail = [&](const std::string& why) {
    throw std::invalid_argument(option + " '" + pattern + "': " + why +
                                "; give one integer conversion for the frame number, e.g. frames/%05d.png");
  };
  bool found = false;
  std::string* out = &prefix_;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') {
      out->push_back(pattern[i]);
      continue;
    }
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      out->push_back('%');
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    bool zero = false;
    if (j < pattern.size() && pattern[j] == '0') zero = true, ++j;
    int width = 0;
    while (j < pattern.size() && pattern[j] >= '0' && pattern[j] <= '9' && width < 100) width = width * 10 + (pattern[j++] - '0');
    if (j >= pattern.size() || (pattern[j] != 'd' && pattern[j] != 'i') || width >= 100)
      // (Built by appending: GCC 12 gives a false -Wrestrict for "'" + std::string + "'".)
      fail(std::string(1, '\'').append(pattern, i, std::min(j + 1, pattern.size()) - i).append("' is not %d, %Nd or %0Nd"));
    if (found) fail("more than one conversion");
    found = true;
    zeroPad_ = zero;
    width_ = width;
    out = &suffix_;
    i = j;
  }
  if (!found) fail("no conversion for the frame number");
}

std::string FramePattern::operator()(std::size_t frame) const {
  std::string number = std::to_string(frame);
  if (number.size() < static_cast<std::size_t>(width_))
    number.insert(0, static_cast<std::size_t>(width_) - number.size(), zeroPad_ ? '0' : ' ');
  return prefix_ + number + suffix_;
}

}  // namespace surftrace::tools
