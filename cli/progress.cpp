#include "cli/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ssgi::cli {
namespace {

// Quiet for the first second; then a bar redrawn at most ten times a second, or a line every five
// seconds when stderr is not a terminal (a log, CI).
constexpr double kQuietSeconds = 1.0;
constexpr double kBarSeconds = 0.1;
constexpr double kLineSeconds = 5.0;

}  // namespace

std::string FormatSeconds(double seconds) {
  char text[32];
  if (seconds >= 60.0) {
    const long total = std::lround(seconds);
    std::snprintf(text, sizeof(text), "%ld min %02ld s", total / 60, total % 60);
  } else {
    std::snprintf(text, sizeof(text), "%.1f s", seconds);
  }
  return text;
}

Progress::Progress(std::string what)
    : what_(std::move(what)), terminal_(::isatty(STDERR_FILENO) != 0), start_(Clock::now()), lastPrint_(start_) {}

Progress::~Progress() {
  if (printed_ && terminal_) std::fprintf(stderr, "\n");
}

std::string Progress::RateText(double count, const std::string& unit) const {
  const double seconds = std::chrono::duration<double>(Clock::now() - start_).count();
  char text[64];
  std::snprintf(text, sizeof(text), "%.2f %s/s", seconds > 0.0 ? count / seconds : 0.0, unit.c_str());
  return text;
}

void Progress::Update(double fraction, const std::string& detail) {
  const Clock::time_point now = Clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double sinceLast = std::chrono::duration<double>(now - lastPrint_).count();
  fraction = std::clamp(fraction, 0.0, 1.0);
  if (elapsed < kQuietSeconds || sinceLast < (terminal_ ? kBarSeconds : kLineSeconds)) return;
  lastPrint_ = now;
  printed_ = true;
  std::string left = "";
  if (fraction > 0.0 && fraction < 1.0) left = ", about " + FormatSeconds(elapsed * (1.0 - fraction) / fraction) + " left";
  const std::string suffix = detail.empty() ? "" : " (" + detail + ")";
  if (terminal_) {
    constexpr int kWidth = 30;
    const int filled = int(fraction * kWidth);
    std::fprintf(stderr, "\r\033[K%s [%s%s] %3d%% %s%s%s", what_.c_str(), std::string(size_t(filled), '#').c_str(),
                 std::string(size_t(kWidth - filled), '.').c_str(), int(fraction * 100.0), FormatSeconds(elapsed).c_str(),
                 left.c_str(), suffix.c_str());
  } else {
    std::fprintf(stderr, "%s: %d%% after %s%s%s\n", what_.c_str(), int(fraction * 100.0), FormatSeconds(elapsed).c_str(),
                 left.c_str(), suffix.c_str());
  }
  std::fflush(stderr);
}

}  // namespace ssgi::cli
