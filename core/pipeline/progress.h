// SPDX-License-Identifier: MIT
// Progress of long stages on stderr: a live percentage on a terminal, plain lines
// otherwise (logs, CI), nothing when quiet.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace dthex {

class Progress {
 public:
  enum class Mode { Quiet, Lines, Live };
  explicit Progress(Mode mode = Mode::Quiet, std::FILE* out = stderr) : mode_(mode), out_(out) {}
  //! Live on a terminal, plain lines otherwise.
  static Mode mode_for(std::FILE* stream, bool quiet);

  void begin(const std::string& stage);
  //! fraction in [0, 1]; throttled, cheap to call often.
  void update(double fraction);
  void end(const std::string& summary);
  void message(const std::string& text);
  //! Report every stage when it ends, not only those that took over a second.
  void set_every_stage(bool every) { every_stage_ = every; }

 private:
  using Clock = std::chrono::steady_clock;
  Mode mode_;
  std::FILE* out_;
  std::string stage_;
  Clock::time_point started_{}, last_update_{};
  int last_percent_ = -1;
  bool every_stage_ = false;
};

}  // namespace dthex
