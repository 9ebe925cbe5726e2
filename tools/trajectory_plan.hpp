// What a `trajectory` run covers: the frames it selects (--frames a:b:step), the share of them
// one process renders (--shard i/n, or a Slurm array task), and the output file names
// (a printf-style pattern with one integer conversion).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace surftrace::tools {

// --frames "a:b:step": frames a, a + step, ... below b (numbered from 0; b and step optional,
// a:b:step like a Python slice without negative numbers; "k" alone is frame k). The frames of
// a file of `frameCount` frames; std::invalid_argument when the text is malformed or selects
// no frame.
std::vector<std::size_t> selectFrames(const std::string& text, std::size_t frameCount);

struct Shard {
  std::size_t index = 0;  // this process renders the i-th selected frame when i mod count == index
  std::size_t count = 1;
  std::string origin;     // "" (all frames), "--shard", or "Slurm array task ..."
};

// --shard "i/n" when given; else SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_COUNT (and
// SLURM_ARRAY_TASK_MIN, for arrays that do not start at 0) from the environment; else one
// shard. std::invalid_argument naming the option or variable and its value when malformed.
Shard chooseShard(const std::string& option, const std::optional<std::string>& taskId,
                  const std::optional<std::string>& taskCount, const std::optional<std::string>& taskMin);
Shard shardFromEnvironment(const std::string& option);

// The selected frames (selectFrames) this shard renders: the i-th of them (from 0) when
// i mod shard.count == shard.index, so that n shards write each selected frame exactly once
// whatever the selection's start and step. Empty when there are fewer selected frames than
// shards and this shard's turn never comes.
std::vector<std::size_t> framesOfShard(const std::vector<std::size_t>& selected, const Shard& shard);

// An output pattern such as "frames/%05d.png": exactly one integer conversion (%d or %i, with
// an optional 0 flag and width), "%%" for a literal percent sign. std::invalid_argument naming
// `option` and what is wrong otherwise.
class FramePattern {
 public:
  FramePattern() = default;
  FramePattern(const std::string& option, const std::string& pattern);
  std::string operator()(std::size_t frame) const;
  bool empty() const { return prefix_.empty() && suffix_.empty(); }
  // Whether the frame number names a folder (frames/%03d/x.png): each frame's own.
  bool numbersFolders() const { return suffix_.find('/') != std::string::npos; }

 private:
  std::string prefix_, suffix_;
  int width_ = 0;
  bool zeroPad_ = false;
};

}  // namespace surftrace::tools
