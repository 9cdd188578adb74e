#include "body/npz.h"

#include <gtest/gtest.h>

#include <cstring>
#include <functional>

#include "core/error.h"
#include "test_support.h"

namespace s2p {
namespace {

NpyArray iota(std::vector<size_t> shape, double scale = 1.0, double offset = 0.0) {
  NpyArray a;
  a.shape = std::move(shape);
  a.data.resize(a.size());
  for (size_t i = 0; i < a.data.size(); ++i) a.data[i] = offset + scale * static_cast<double>(i);
  return a;
}

// A .npy image built by hand, as numpy lays it out: magic, version, header length, header
// padded with spaces to a multiple of 64 and ended by '\n', then raw little-endian data.
std::string handNpy(int major, const std::string& dict, const std::string& data) {
  std::string header = dict;
  const size_t prefix = major == 1 ? 10 : 12;
  header.append((64 - (prefix + header.size() + 1) % 64) % 64, ' ');
  header += '\n';
  std::string out = "\x93NUMPY";
  out += static_cast<char>(major);
  out += '\0';
  const uint32_t len = static_cast<uint32_t>(header.size());
  out.append(reinterpret_cast<const char*>(&len), major == 1 ? 2 : 4);
  return out + header + data;
}

std::string doubles(std::initializer_list<double> v) {
  std::string s;
  for (double d : v) s.append(reinterpret_cast<const char*>(&d), 8);
  return s;
}

template <class E>
std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "(no exception)";
}

TEST(Npz, RoundTripOfDtypesShapesOrdersAndCompression) {
  test::TempDir dir;
  std::vector<NpzEntry> entries;
  entries.push_back({"f8", iota({3, 4}, 0.1, -0.55), "<f8", false, false, {}});
  entries.push_back({"f4_fortran", iota({2, 3, 4}, 0.25, -2.0), "<f4", true, true, {}});
  entries.push_back({"i4", iota({7}, -3.0, 5.0), "<i4", false, true, {}});
  entries.push_back({"i8_fortran", iota({2, 5}, 1099511627776.0, -7.0), "<i8", true, false, {}});
  NpyArray u4 = iota({2, 2});
  u4.data[3] = 4294967295.0;  // SMPL's root parent in kintree_table
  entries.push_back({"u4", u4, "<u4", false, true, {}});
  NpyArray scalar;
  scalar.data = {200};
  entries.push_back({"u1_scalar", scalar, "|u1", false, false, {}});
  NpyArray flags = iota({5});
  flags.data = {0, 1, 1, 0, 1};
  entries.push_back({"b1", flags, "|b1", false, true, {}});
  entries.push_back({"empty", iota({0, 3}), "<f8", false, false, {}});
  writeNpz(dir / "a.npz", entries);

  const auto arrays = readNpz(dir / "a.npz");
  ASSERT_EQ(arrays.size(), entries.size());
  for (const NpzEntry& e : entries) {
    ASSERT_TRUE(arrays.count(e.name)) << e.name;
    const NpyArray& a = arrays.at(e.name);
    EXPECT_EQ(a.shape, e.array.shape) << e.name;
    EXPECT_EQ(a.data, e.array.data) << e.name;  // exact: every value is representable
  }
  EXPECT_EQ(arrays.at("f4_fortran").at({1, 2, 3}), -2.0 + 0.25 * 23);
  EXPECT_TRUE(arrays.at("u1_scalar").shape.empty());
}

TEST(Npz, FortranOrderFollowsNumpyLayout) {
  // numpy.asfortranarray(np.arange(6.).reshape(2, 3)) stores 0 3 1 4 2 5 in memory.
  const std::string f = handNpy(1, "{'descr': '<f8', 'fortran_order': True, 'shape': (2, 3), }",
                                doubles({0, 3, 1, 4, 2, 5}));
  const NpyArray a = decodeNpy(f, "hand");
  ASSERT_EQ(a.shape, (std::vector<size_t>{2, 3}));
  EXPECT_EQ(a.data, (std::vector<double>{0, 1, 2, 3, 4, 5}));
  // Our writer lays Fortran data out the same way.
  const std::string mine = encodeNpy(iota({2, 3}), "<f8", true);
  EXPECT_EQ(mine.substr(mine.size() - 48), doubles({0, 3, 1, 4, 2, 5}));
  // Header versions 2.0 and 3.0 have a 4-byte header length.
  for (int major : {2, 3}) {
    const NpyArray b =
        decodeNpy(handNpy(major, "{'descr': '<f8', 'fortran_order': False, 'shape': (3,), }",
                          doubles({1.5, -2, 7})),
                  "v" + std::to_string(major));
    EXPECT_EQ(b.data, (std::vector<double>{1.5, -2, 7}));
  }
}

TEST(Npz, BadNpyHeadersAreFormatErrors) {
  const std::string data = doubles({1, 2});
  EXPECT_THROW(decodeNpy("not numpy at all", "x"), FormatError);
  EXPECT_THROW(
      decodeNpy(handNpy(1, "{'descr': '|O', 'fortran_order': False, 'shape': (2,), }", data), "x"),
      FormatError);
  EXPECT_NE(messageOf<FormatError>([&] {
              decodeNpy(
                  handNpy(1, "{'descr': '|O', 'fortran_order': False, 'shape': (2,), }", data),
                  "x");
            }).find("|O"),
            std::string::npos);
  for (const char* bad : {"{'descr': '>f8', 'fortran_order': False, 'shape': (2,), }",
                          "{'descr': '<c16', 'fortran_order': False, 'shape': (1,), }",
                          "{'descr': [('a', '<f8')], 'fortran_order': False, 'shape': (1,), }",
                          "{'descr': '<f8', 'fortran_order': Maybe, 'shape': (2,), }",
                          "{'descr': '<f8', 'fortran_order': False, 'shape': (x,), }",
                          "{'descr': '<f8', 'fortran_order': False, }",
                          "{'descr': '<f8', 'fortran_order': False, 'shape': (3,), }"})
    EXPECT_THROW(decodeNpy(handNpy(1, bad, data), "x"), FormatError) << bad;
  std::string v9 = handNpy(1, "{'descr': '<f8', 'fortran_order': False, 'shape': (2,), }", data);
  v9[6] = 9;
  EXPECT_THROW(decodeNpy(v9, "x"), FormatError);
  // Header length beyond the data.
  std::string longHeader = v9;
  longHeader[6] = 1;
  longHeader[8] = '\xff';
  longHeader[9] = '\xff';
  EXPECT_THROW(decodeNpy(longHeader, "x"), FormatError);
}

TEST(Npz, CorruptArchivesAreFormatErrorsNamingFileAndEntry) {
  test::TempDir dir;
  std::vector<NpzEntry> entries;
  entries.push_back({"first", iota({50, 3}, 0.5), "<f8", false, false, {}});
  entries.push_back({"second", iota({40}), "<i4", false, true, {}});
  writeNpz(dir / "ok.npz", entries);
  const std::string good = test::readFile(dir / "ok.npz");

  test::writeFile(dir / "truncated.npz", good.substr(0, good.size() / 2));
  EXPECT_THROW(readNpz(dir / "truncated.npz"), FormatError);
  test::writeFile(dir / "tail_cut.npz", good.substr(0, good.size() - 5));
  EXPECT_THROW(readNpz(dir / "tail_cut.npz"), FormatError);

  test::writeFile(dir / "magic.npz", "GIF89a this is not a zip archive at all, sorry........");
  const std::string magic = messageOf<FormatError>([&] { readNpz(dir / "magic.npz"); });
  EXPECT_NE(magic.find("magic.npz"), std::string::npos) << magic;

  // One flipped data byte in the stored entry: the CRC-32 catches it.
  std::string flipped = good;
  flipped[200] ^= 0x40;
  test::writeFile(dir / "crc.npz", flipped);
  const std::string crc = messageOf<FormatError>([&] { readNpz(dir / "crc.npz"); });
  EXPECT_NE(crc.find("first"), std::string::npos) << crc;
  EXPECT_NE(crc.find("CRC"), std::string::npos) << crc;

  // A well-formed zip holding a bad .npy header: the error names the entry.
  std::vector<NpzEntry> bad;
  bad.push_back(
      {"weights",
       {},
       "<f8",
       false,
       true,
       handNpy(1, "{'descr': '<f8', 'fortran_order': False, 'shape': (9,), }", doubles({1, 2}))});
  writeNpz(dir / "bad_header.npz", bad);
  const std::string hdr = messageOf<FormatError>([&] { readNpz(dir / "bad_header.npz"); });
  EXPECT_NE(hdr.find("weights"), std::string::npos) << hdr;
  EXPECT_NE(hdr.find("bad_header.npz"), std::string::npos) << hdr;

  // A compressed entry whose central record declares 3 GB: refused before it is allocated
  // (found by fuzzing: the reader used to reserve the declared size first).
  std::string huge = good;
  const size_t second = huge.rfind("second.npy") - 46;  // its central directory record
  ASSERT_EQ(huge.compare(second, 4, std::string("PK\x01\x02", 4)), 0);
  const uint32_t threeGb = 3000000000u;
  std::memcpy(&huge[second + 24], &threeGb, 4);
  test::writeFile(dir / "huge.npz", huge);
  const std::string big = messageOf<FormatError>([&] { readNpz(dir / "huge.npz"); });
  EXPECT_NE(big.find("3000000000"), std::string::npos) << big;
  EXPECT_NE(big.find("second"), std::string::npos) << big;

  // Zip64 end record markers are refused clearly.
  std::string zip64 = good;
  const size_t eocd = zip64.size() - 22;
  zip64[eocd + 10] = zip64[eocd + 11] = '\xff';
  test::writeFile(dir / "zip64.npz", zip64);
  EXPECT_NE(messageOf<FormatError>([&] { readNpz(dir / "zip64.npz"); }).find("zip64"),
            std::string::npos);
}

TEST(Npz, MissingFileIsIoErrorNotFormatError) {
  test::TempDir dir;
  bool io = false, format = false;
  try {
    readNpz(dir / "nope.npz");
  } catch (const FormatError&) {
    format = true;
  } catch (const IoError&) {
    io = true;
  }
  EXPECT_TRUE(io);
  EXPECT_FALSE(format);
  EXPECT_THROW(readNpy(dir / "nope.npy"), IoError);
}

}  // namespace
}  // namespace s2p
