#include "cli_progress.hpp"

#include <algorithm>
#include <cstdio>

namespace fracref::cli {

ProgressLine::ProgressLine(bool enabled) : enabled_(enabled) {}

ProgressLine::~ProgressLine() { done(); }

void ProgressLine::update(const std::string& stage, double fraction, const std::string& detail) {
  if (!enabled_) return;
  const int width = 24;
  int filled = int(std::clamp(fraction, 0.0, 1.0) * width + 0.5);
  std::string bar(filled, '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "\r\033[K%-10s [%s] %3d%%  %s", stage.c_str(), bar.c_str(), int(fraction * 100 + 0.5),
               detail.c_str());
  std::fflush(stderr);
  shown_ = true;
}

void ProgressLine::done() {
  if (enabled_ && shown_) std::fprintf(stderr, "\r\033[K");
  shown_ = false;
}

}  // namespace fracref::cli
