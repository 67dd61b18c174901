// SPDX-License-Identifier: MIT
#include <dthex/pipeline/progress.h>

#include <algorithm>
#include <unistd.h>

namespace dthex {

Progress::Mode Progress::mode_for(std::FILE* stream, bool quiet) {
  if (quiet) return Mode::Quiet;
  return ::isatty(::fileno(stream)) ? Mode::Live : Mode::Lines;
}

void Progress::begin(const std::string& stage) {
  stage_ = stage;
  started_ = last_update_ = Clock::now();
  last_percent_ = -1;
  if (mode_ == Mode::Live) {
    std::fprintf(out_, "\r  %-22s ...", stage_.c_str());
    std::fflush(out_);
  }
}

void Progress::update(double fraction) {
  if (mode_ == Mode::Quiet) return;
  const int percent = std::clamp(int(fraction * 100.0), 0, 100);
  const auto now = Clock::now();
  const double since_start = std::chrono::duration<double>(now - started_).count();
  if (percent == last_percent_) return;
  if (mode_ == Mode::Live) {
    if (std::chrono::duration<double>(now - last_update_).count() < 0.1) return;
    const int width = 30, filled = percent * width / 100;
    std::fprintf(out_, "\r  %-22s [%s%s] %3d%%", stage_.c_str(), std::string(size_t(filled), '#').c_str(),
                 std::string(size_t(width - filled), '.').c_str(), percent);
    std::fflush(out_);
  } else {
    // Plain lines: only for stages that already took a second, every 25%.
    if (since_start < 1.0 || percent / 25 == last_percent_ / 25) return;
    std::fprintf(out_, "  %s: %d%%\n", stage_.c_str(), percent);
  }
  last_percent_ = percent;
  last_update_ = now;
}

void Progress::end(const std::string& summary) {
  if (mode_ == Mode::Quiet) return;
  const double seconds = std::chrono::duration<double>(Clock::now() - started_).count();
  // The summary table repeats every stage: keep only the long ones on record.
  if (mode_ == Mode::Live) std::fprintf(out_, "\r\033[K");
  if (seconds >= 1.0 || every_stage_) std::fprintf(out_, "  %-22s %8.2f s  %s\n", stage_.c_str(), seconds, summary.c_str());
  std::fflush(out_);
}

void Progress::message(const std::string& text) {
  if (mode_ == Mode::Quiet) return;
  std::fprintf(out_, "%s\n", text.c_str());
  std::fflush(out_);
}

}  // namespace dthex
