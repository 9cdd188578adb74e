#include "core/progress.h"

#include <algorithm>
#include <fmt/format.h>
#include <unistd.h>

namespace s2p {

Progress::Progress(Mode mode, std::FILE* stream) : mode_(mode), stream_(stream) {
  if (mode_ == Mode::Auto) mode_ = isatty(fileno(stream_)) ? Mode::Terminal : Mode::Plain;
}

Progress& Progress::silent() {
  static Progress p(Mode::Silent);
  return p;
}

void Progress::begin(const std::string& stage, long total) {
  if (active_) end();
  stage_ = stage;
  total_ = total;
  done_ = 0;
  active_ = true;
  start_ = std::chrono::steady_clock::now();
  cpuStart_ = std::clock();
  lastDraw_ = {};
  if (mode_ == Mode::Plain) fmt::print(stream_, "{} ...\n", stage_);
  draw(true);
}

void Progress::update(long done) {
  done_ = done;
  draw(false);
}

double Progress::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

double Progress::cpuSeconds() const {
  return static_cast<double>(std::clock() - cpuStart_) / CLOCKS_PER_SEC;
}

void Progress::end() {
  if (!active_) return;
  active_ = false;
  if (mode_ == Mode::Terminal) {
    fmt::print(stream_, "\r\033[K{} done in {:.2f} s\n", stage_, elapsed());
  } else if (mode_ == Mode::Plain) {
    fmt::print(stream_, "{} done in {:.2f} s ({:.2f} s CPU)\n", stage_, elapsed(), cpuSeconds());
  }
  std::fflush(stream_);
}

void Progress::message(const std::string& text) {
  if (mode_ == Mode::Silent) return;
  if (mode_ == Mode::Terminal && active_) fmt::print(stream_, "\r\033[K");
  fmt::print(stream_, "{}\n", text);
  if (mode_ == Mode::Terminal && active_) draw(true);
  std::fflush(stream_);
}

void Progress::draw(bool force) {
  if (mode_ != Mode::Terminal || !active_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - lastDraw_ < std::chrono::milliseconds(50)) return;
  lastDraw_ = now;
  if (total_ > 0) {
    constexpr int kWidth = 30;
    const double frac = std::min(1.0, static_cast<double>(done_) / total_);
    const int filled = static_cast<int>(frac * kWidth);
    fmt::print(stream_, "\r\033[K{} [{}{}] {:3d}% {:.1f} s", stage_, std::string(filled, '#'),
               std::string(kWidth - filled, ' '), static_cast<int>(100 * frac), elapsed());
  } else {
    fmt::print(stream_, "\r\033[K{} ... {:.1f} s", stage_, elapsed());
  }
  std::fflush(stream_);
}

}  // namespace s2p
