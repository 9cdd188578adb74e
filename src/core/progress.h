// Progress of long steps. On a terminal it redraws one line on stderr ("fit  [#####     ] 52%");
// when stderr is not a terminal it writes one plain line per stage start and end (so CI logs
// and files stay readable), or nothing at all when silenced.
#pragma once

#include <chrono>
#include <ctime>
#include <cstdio>
#include <string>

namespace s2p {

class Progress {
 public:
  enum class Mode { Auto, Terminal, Plain, Silent };

  // `stream` defaults to stderr; Auto picks Terminal when the stream is a tty, else Plain.
  explicit Progress(Mode mode = Mode::Auto, std::FILE* stream = stderr);

  // Starts a named stage with `total` steps (0 when the number of steps is unknown).
  void begin(const std::string& stage, long total = 0);
  // Reports that `done` of `total` steps are finished (throttled: at most ~20 redraws/s).
  void update(long done);
  // Ends the current stage and prints its duration.
  void end();
  // A message that interrupts the progress line (warnings, notes).
  void message(const std::string& text);

  Mode mode() const { return mode_; }
  // Seconds since begin() of the current or last stage.
  double elapsed() const;
  // Processor seconds of the whole process (every thread) since begin(): next to elapsed(), it
  // shows how well a stage uses the cores, and it barely moves when other programs load them.
  double cpuSeconds() const;

  // A progress object that prints nothing: the default for library calls.
  static Progress& silent();

 private:
  void draw(bool force);

  Mode mode_;
  std::FILE* stream_;
  std::string stage_;
  long total_ = 0;
  long done_ = 0;
  bool active_ = false;
  std::chrono::steady_clock::time_point start_;
  std::clock_t cpuStart_ = 0;
  std::chrono::steady_clock::time_point lastDraw_;
};

}  // namespace s2p
