#pragma once
// A one-line progress display on stderr, shown only when stderr is a terminal.
#include <string>

namespace fracref::cli {

class ProgressLine {
 public:
  explicit ProgressLine(bool enabled);
  ~ProgressLine();
  void update(const std::string& stage, double fraction, const std::string& detail);
  void done();

 private:
  bool enabled_;
  bool shown_ = false;
};

}  // namespace fracref::cli
