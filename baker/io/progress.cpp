#include "io/progress.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <unistd.h>

namespace clothbake::io {

namespace {

/// Percent between two progress lines when stderr is not a terminal: 10, or
/// 1 when the environment sets CLOTHBAKE_PROGRESS=lines (the Blender add-on
/// reads these lines to drive its progress bar).
int line_step_percent() {
  const char* mode = std::getenv("CLOTHBAKE_PROGRESS");
  return mode != nullptr && std::strcmp(mode, "lines") == 0 ? 1 : 10;
}

}  // namespace

ProgressBar::ProgressBar(std::string label, bool quiet)
    : m_label(std::move(label)),
      m_quiet(quiet),
      m_tty(::isatty(STDERR_FILENO) != 0),
      m_start(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() {
  if (!m_finished && m_last_shown >= 0 && m_tty && !m_quiet) std::fputc('\n', stderr);
}

void ProgressBar::update(double fraction) {
  if (m_quiet) return;
  const int percent = std::clamp(int(fraction * 100.0), 0, 100);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
  if (m_tty) {
    if (percent == m_last_shown) return;
    m_last_shown = percent;
    constexpr int width = 30;
    const int filled = percent * width / 100;
    std::fprintf(stderr, "\r%s [%.*s%*s] %3d%% %6.1fs", m_label.c_str(), filled,
                 "##############################", width - filled, "", percent, seconds);
    std::fflush(stderr);
  } else {
    static const int step = line_step_percent();
    const int shown = percent / step;
    if (shown == m_last_shown) return;
    m_last_shown = shown;
    std::fprintf(stderr, "%s %3d%% %.1fs\n", m_label.c_str(), shown * step, seconds);
  }
}

void ProgressBar::finish() {
  if (m_quiet || m_finished) return;
  m_finished = true;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
  if (m_tty) std::fputc('\r', stderr);
  std::fprintf(stderr, "%s done in %.2fs%s\n", m_label.c_str(), seconds,
               m_tty ? "                                        " : "");
}

}  // namespace clothbake::io
