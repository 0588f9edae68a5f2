// Progress of a long command on stderr, so that a run of minutes is never silent: on a terminal a
// bar redrawn in place with the time left; piped, a line every few seconds. Work that ends within
// a second prints nothing.
#pragma once

#include <chrono>
#include <string>

namespace ssgi::cli {

class Progress {
 public:
  explicit Progress(std::string what);
  ~Progress();  // ends a bar's line
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // Reports `fraction` (0 to 1) of the work done; `detail` names what was just done. Called from
  // one thread.
  void Update(double fraction, const std::string& detail = "");
  // "8.1 views/s": `count` items of `unit` over the time since the start.
  std::string RateText(double count, const std::string& unit) const;

 private:
  using Clock = std::chrono::steady_clock;
  std::string what_;
  bool terminal_;
  Clock::time_point start_, lastPrint_;
  bool printed_ = false;
};

// "1 min 05 s", "12.3 s": a duration for messages.
std::string FormatSeconds(double seconds);

}  // namespace ssgi::cli
