#include "export/png.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "core/error.h"
#include "test_support.h"

namespace s2p {
namespace {

// A deterministic pattern that exercises every byte value and an odd width (row padding).
Image patternImage(int w, int h) {
  Image image;
  image.width = w;
  image.height = h;
  image.rgb.resize(std::size_t(w) * h * 3);
  for (std::size_t i = 0; i < image.rgb.size(); ++i)
    image.rgb[i] = static_cast<std::uint8_t>((i * 7919 + i / 3) % 256);
  return image;
}

bool folderIsEmpty(const std::filesystem::path& dir) {
  return std::filesystem::directory_iterator(dir) == std::filesystem::directory_iterator();
}

TEST(Png, RoundTripIsExact) {
  test::TempDir dir;
  const Image image = patternImage(37, 23);
  writePng(dir / "a.png", image);
  const Image back = readPng(dir / "a.png");
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 23);
  EXPECT_EQ(back.rgb, image.rgb);
  // A PNG starts with its 8-byte signature.
  EXPECT_EQ(test::readFile(dir / "a.png").substr(1, 3), "PNG");
}

TEST(Png, OverwritesAtomicallyAndLeavesNoTemporaryFile) {
  test::TempDir dir;
  writePng(dir / "a.png", patternImage(5, 4));
  writePng(dir / "a.png", patternImage(9, 2));
  EXPECT_EQ(readPng(dir / "a.png").width, 9);
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 1);
}

TEST(Png, UnwritableDestinationThrowsIoErrorAndLeavesNoFile) {
  test::TempDir dir;
  const Image image = patternImage(4, 4);
  EXPECT_THROW(writePng(dir / "missing" / "a.png", image), IoError);
  // A parent that is a regular file cannot hold files, even for root.
  test::writeFile(dir / "file", "x");
  EXPECT_THROW(writePng(dir / "file" / "a.png", image), IoError);
  EXPECT_FALSE(std::filesystem::exists(dir / "missing"));
  EXPECT_EQ(test::readFile(dir / "file"), "x");
  // A read-only folder (permissions do not stop root, so only checked for other users).
  if (geteuid() != 0) {
    std::filesystem::create_directory(dir / "ro");
    ::chmod((dir / "ro").c_str(), 0500);
    EXPECT_THROW(writePng(dir / "ro" / "a.png", image), IoError);
    EXPECT_TRUE(folderIsEmpty(dir / "ro"));
    ::chmod((dir / "ro").c_str(), 0700);
  }
}

TEST(Png, InvalidImageIsAnInputError) {
  test::TempDir dir;
  Image image = patternImage(4, 4);
  image.rgb.pop_back();
  EXPECT_THROW(writePng(dir / "a.png", image), InputError);
  EXPECT_THROW(writePng(dir / "b.png", Image{}), InputError);
  EXPECT_TRUE(folderIsEmpty(dir.path()));
}

TEST(Png, ReadErrorsAreTyped) {
  test::TempDir dir;
  EXPECT_THROW(readPng(dir / "none.png"), IoError);
  test::writeFile(dir / "garbage.png", "this is not a png at all");
  EXPECT_THROW(readPng(dir / "garbage.png"), FormatError);
  writePng(dir / "good.png", patternImage(64, 64));
  const std::string bytes = test::readFile(dir / "good.png");
  test::writeFile(dir / "truncated.png", bytes.substr(0, bytes.size() / 2));
  EXPECT_THROW(readPng(dir / "truncated.png"), FormatError);
  test::writeFile(dir / "empty.png", "");
  EXPECT_THROW(readPng(dir / "empty.png"), FormatError);
}

}  // namespace
}  // namespace s2p
