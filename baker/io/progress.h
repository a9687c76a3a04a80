#pragma once
/// A progress bar on stderr for long jobs. On a terminal it redraws one line;
/// otherwise (logs, CI) it prints a line every 10 percent, or every percent
/// when CLOTHBAKE_PROGRESS=lines (the Blender add-on reads those). Thread-compatible:
/// callers serialise update() (the renderer does).

#include <chrono>
#include <string>

namespace clothbake::io {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label, bool quiet = false);
  ~ProgressBar();
  void update(double fraction);
  /// Ends the line with the total time.
  void finish();

 private:
  std::string m_label;
  bool m_quiet, m_tty, m_finished = false;
  int m_last_shown = -1;
  std::chrono::steady_clock::time_point m_start;
};

}  // namespace clothbake::io
