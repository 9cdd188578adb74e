#include "core/progress.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

namespace s2p {
namespace {

// Everything the progress object wrote to its stream.
std::string contents(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string out;
  char buf[256];
  while (size_t n = std::fread(buf, 1, sizeof buf, f)) out.append(buf, n);
  return out;
}

TEST(Progress, PlainModeWritesOneLinePerStageStartAndEnd) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    Progress p(Progress::Mode::Plain, f);
    p.begin("fit", 10);
    for (int i = 0; i < 10; ++i) p.update(i);
    p.message("warning: something");
    p.end();
  }
  const std::string out = contents(f);
  std::fclose(f);
  EXPECT_NE(out.find("fit ...\n"), std::string::npos);
  EXPECT_NE(out.find("warning: something\n"), std::string::npos);
  EXPECT_NE(out.find("fit done in "), std::string::npos);
  EXPECT_EQ(out.find('\r'), std::string::npos);  // no terminal redraws in a log
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 3);
}

TEST(Progress, SilentModeWritesNothing) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  Progress p(Progress::Mode::Silent, f);
  p.begin("segment", 3);
  p.update(2);
  p.message("hello");
  p.end();
  EXPECT_TRUE(contents(f).empty());
  std::fclose(f);
}

TEST(Progress, AutoModeIsPlainWhenTheStreamIsNotATerminal) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(Progress(Progress::Mode::Auto, f).mode(), Progress::Mode::Plain);
  std::fclose(f);
}

TEST(Progress, TerminalModeRedrawsOneLineWithABar) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  Progress p(Progress::Mode::Terminal, f);
  p.begin("cut", 4);
  p.update(4);
  p.end();
  const std::string out = contents(f);
  std::fclose(f);
  EXPECT_NE(out.find('\r'), std::string::npos);
  EXPECT_NE(out.find("cut ["), std::string::npos);
  EXPECT_NE(out.find("cut done in "), std::string::npos);
}

}  // namespace
}  // namespace s2p
