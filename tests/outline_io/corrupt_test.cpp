// Corrupt files: each gives a ReadError whose message names the file, the line (text) or byte offset
// (binary) worked out here by hand, and what is wrong. Random garbage never gives anything else.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <limits>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "outline_io/cloud.hpp"

using namespace hg::outline_io;

namespace {

std::string slurp(const std::string& name) {
  std::ifstream f(std::string(HG_TEST_DATA) + "/outline_io/" + name, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const ReadError& e) {
    return e.what();
  }
  return "<no error>";
}

// The message starts with "NAME: WHERE: " and contains `what`.
void expect_error(const std::string& msg, const std::string& name, const std::string& where, const std::string& what) {
  const bool numbered = !where.empty() && std::isdigit(static_cast<unsigned char>(where.back()));
  EXPECT_EQ(msg.rfind(name + ": " + where + (numbered ? ": " : " "), 0), 0u) << msg;
  EXPECT_NE(msg.find(what), std::string::npos) << msg << "\n  (expected: " << what << ")";
}

std::string text(std::string_view s) {
  return error_of([&] { parse_text_cloud(s, "bad.xyz"); });
}
std::string pcd(std::string_view s) {
  return error_of([&] { parse_pcd(s, "bad.pcd"); });
}
std::string ply(std::string_view s) {
  return error_of([&] { parse_ply(s, "bad.ply"); });
}

const std::string kPcdHead =
    "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\n";

// NaN/Inf values are no error: the point is kept (indices stay file positions) and counted once.
void expect_kept(const Cloud& c, std::size_t points, std::size_t point, int axis, double value) {
  ASSERT_EQ(c.size(), points);
  EXPECT_EQ(c.nonfinite, 1u);
  const double v = c.xyz[3 * point + axis];
  if (std::isnan(value)) EXPECT_TRUE(std::isnan(v)) << v;
  else
    EXPECT_EQ(v, value);
}

std::string f32s(std::initializer_list<float> v) {
  std::string s(v.size() * 4, '\0');
  std::memcpy(s.data(), std::data(v), s.size());
  return s;
}

}  // namespace

TEST(OutlineIoCorrupt, TextBadNumberNamesLineAndToken) {
  expect_error(text("1 2\n3 x\n"), "bad.xyz", "line 2", "bad number 'x' for y");
  expect_error(text("1 2\n\x01\xff 3\n"), "bad.xyz", "line 2", "bad number '\\x01\\xff' for x");
  expect_error(text("x y\nfoo bar\n"), "bad.xyz", "line 2", "bad number 'foo'");  // only one header line
  expect_error(text("1 2\n1e999 2\n"), "bad.xyz", "line 2", "out of range");
}

TEST(OutlineIoCorrupt, TextNanInfAndCounts) {
  expect_kept(parse_text_cloud("1 2\n# c\nnan 3\n", "t.xyz"), 2, 1, 0, std::nan(""));
  expect_kept(parse_text_cloud("1 2 inf\n", "t.xyz"), 1, 0, 2, INFINITY);
  expect_error(text("1 2 3\n4 5\n"), "bad.xyz", "line 2", "wrong number of values: 2 (earlier lines have 3)");
  expect_error(text("1\n"), "bad.xyz", "line 1", "expected x y [z]");
  expect_error(text("1,,2\n"), "bad.xyz", "line 1", "empty field in column 2");
  expect_error(text("1,2,\n"), "bad.xyz", "line 1", "empty field in column 3");
  EXPECT_EQ(text("# nothing\n\n"), "bad.xyz: no points in file");
  EXPECT_EQ(text(""), "bad.xyz: no points in file");
}

TEST(OutlineIoCorrupt, FileLevelErrors) {
  EXPECT_EQ(error_of([] { read_cloud_file("/nonexistent/dir/a.xyz"); }),
            "/nonexistent/dir/a.xyz: cannot open file: no such file");
  EXPECT_EQ(error_of([] { read_cloud_file(HG_TEST_DATA); }).find("unsupported format"),
            std::string(HG_TEST_DATA).size() + 2);
  const std::string dir = std::string(HG_TEST_DATA) + "/outline_io.xyz";  // not a file name that exists
  EXPECT_NE(error_of([&] { read_cloud_file(dir); }).find("no such file"), std::string::npos);
}

TEST(OutlineIoCorrupt, PcdHeaderErrorsNameTheLine) {
  expect_error(pcd("FIELDS x y\nSIZE 4\n"), "bad.pcd", "line 2", "SIZE has 1 values for 2 fields");
  expect_error(pcd("FIELDS x y\nSIZE 4 2\nTYPE F F\nWIDTH 1\nDATA ascii\n1 2\n"), "bad.pcd", "line",
               "TYPE F with SIZE 2");
  expect_error(pcd("FIELDS a b\nSIZE 4 4\nTYPE F F\nWIDTH 1\nDATA ascii\n1 2\n"), "bad.pcd", "line 5", "no x and y");
  expect_error(pcd("FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 3\nHEIGHT 2\nPOINTS 5\nDATA ascii\n"), "bad.pcd", "line 6",
               "wrong counts: POINTS 5 but WIDTH x HEIGHT = 3 x 2 = 6");
  expect_error(pcd("FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 1\nDATA binary_lz4\n"), "bad.pcd", "line 5",
               "unsupported format: DATA 'binary_lz4'");
  expect_error(pcd("FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 1\n"), "bad.pcd", "line 4", "file ends before the DATA line");
  expect_error(pcd("FIELDS x y\nFOO 1\n"), "bad.pcd", "line 2", "unknown keyword 'FOO'");
  expect_error(pcd("\x89PNG\r\n\x1a\n\0\0\0"), "bad.pcd", "line", "");
}

TEST(OutlineIoCorrupt, PcdAsciiDataErrors) {
  const std::string head = kPcdHead + "DATA ascii\n";  // data starts on line 10
  expect_error(pcd(head + "1 2 3\n"), "bad.pcd", "line 10", "truncated data: 1 points found, header declares 2");
  expect_error(pcd(head + "1 2 3\n4 5\n"), "bad.pcd", "line 11", "wrong number of values: 2");
  expect_error(pcd(head + "1 2 3\n4 5 6\n7 8 9\n"), "bad.pcd", "line 12", "more data lines than the 2 points");
  expect_kept(parse_pcd(head + "1 2 3\nnan 5 6\n", "t.pcd"), 2, 1, 0, std::nan(""));
  expect_error(pcd(head + "1 2 3\n4 five 6\n"), "bad.pcd", "line 11", "bad number 'five' for y");
}

TEST(OutlineIoCorrupt, PcdBinaryErrorsNameTheByte) {
  const std::string head = kPcdHead + "DATA binary\n";
  const std::string body = f32s({1, 2, 3, 4, 5, 6});
  // Truncated: the error is where the file ends.
  std::string cut = head + body.substr(0, 20);
  expect_error(pcd(cut), "bad.pcd", "byte " + std::to_string(cut.size()),
               "truncated data: 2 points of 12 bytes need 24 bytes");
  // Extra bytes after the declared points.
  expect_error(pcd(head + body + "XYZ"), "bad.pcd", "byte " + std::to_string(head.size() + 24),
               "3 bytes of unexpected data");
  // NaN y of point 1 (a no-return pixel): kept and counted.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  expect_kept(parse_pcd(head + f32s({1, 2, 3, 4, nan, 6}), "t.pcd"), 2, 1, 1, std::nan(""));
  // A header that claims far more points than the file holds must not allocate them.
  std::string huge = "FIELDS x y\nSIZE 8 8\nTYPE F F\nWIDTH 1000000000000\nHEIGHT 1\nDATA binary\n" + body;
  expect_error(pcd(huge), "bad.pcd", "byte " + std::to_string(huge.size()), "truncated data: 1000000000000 points");
  std::string overflow = "FIELDS x y\nSIZE 8 8\nTYPE F F\nWIDTH 4294967296\nHEIGHT 4294967296\nDATA binary\n";
  expect_error(pcd(overflow), "bad.pcd", "line 6", "overflows");
  std::string ascii_huge = "FIELDS x y\nSIZE 8 8\nTYPE F F\nWIDTH 100000000000\nPOINTS 100000000000\nDATA ascii\n1 2\n";
  expect_error(pcd(ascii_huge), "bad.pcd", "line 7", "truncated data: 1 points found, header declares 100000000000");
}

TEST(OutlineIoCorrupt, PcdCompressedErrors) {
  const std::string head = kPcdHead + "DATA binary_compressed\n";
  const std::string raw = f32s({1, 4, 2, 5, 3, 6});  // x[], y[], z[]
  auto block = [&](std::uint32_t csize, std::uint32_t usize, const std::string& payload) {
    std::string s = head;
    s.append(reinterpret_cast<const char*>(&csize), 4);
    s.append(reinterpret_cast<const char*>(&usize), 4);
    return s + payload;
  };
  const std::string literal = std::string(1, static_cast<char>(raw.size() - 1)) + raw;  // one literal run of 24 bytes
  // Sanity: the well-formed block reads.
  Cloud ok = parse_pcd(block(static_cast<std::uint32_t>(literal.size()), 24, literal), "ok.pcd");
  ASSERT_EQ(ok.size(), 2u);
  EXPECT_EQ(ok.xyz[3], 4.0);
  EXPECT_EQ(ok.xyz[5], 6.0);
  const std::size_t block_at = head.size() + 8;
  expect_error(pcd(block(25, 23, literal)), "bad.pcd", "byte " + std::to_string(head.size() + 4),
               "wrong counts: uncompressed size 23");
  expect_error(pcd(block(40, 24, literal)), "bad.pcd", "byte " + std::to_string(block_at + 25),
               "truncated data: compressed block of 40 bytes");
  expect_error(pcd(block(10, 24, literal.substr(0, 10))), "bad.pcd", "byte " + std::to_string(block_at),
               "LZF literal run of 24 bytes runs past");
  // Back reference before the start of the output: ctrl 0x20 (length 3), distance 1 with nothing decoded yet.
  expect_error(pcd(block(2, 24, std::string("\x20\x00", 2))), "bad.pcd", "byte " + std::to_string(block_at),
               "before the start of the output");
  // A block that decodes to fewer bytes than declared.
  std::string short_lit = std::string(1, 3) + raw.substr(0, 4);
  expect_error(pcd(block(5, 24, short_lit)), "bad.pcd", "byte " + std::to_string(block_at + 5),
               "decodes to 4 bytes, header declares 24");
  // Impossible ratio: 1 compressed byte cannot make 24 MB.
  std::string big = "FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 3000000\nDATA binary_compressed\n";
  std::uint32_t sizes[2] = {1, 24000000};
  big.append(reinterpret_cast<const char*>(sizes), 8);
  big += '\0';
  expect_error(pcd(big), "bad.pcd", "byte", "impossible from 1 compressed bytes");
}

TEST(OutlineIoCorrupt, PlyErrors) {
  expect_error(ply("pcd\n"), "bad.ply", "line 1", "does not start with 'ply'");
  expect_error(
      ply("ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n"),
      "bad.ply", "line 2", "unsupported format 'binary_big_endian'");
  expect_error(ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty flaot y\nend_header\n1 2\n"),
               "bad.ply", "line 5", "unknown type 'flaot'");
  expect_error(ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float q\nend_header\n1 2\n"),
               "bad.ply", "line 3", "no x and y");
  const std::string ahead =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";  // data from line 9
  expect_error(ply(ahead + "1 2\n3\n"), "bad.ply", "line 10", "line ends before property 'y'");
  expect_error(ply(ahead + "1 2\n3 4 5\n"), "bad.ply", "line 10", "wrong number of values: 3");
  expect_error(ply(ahead + "1 2\n3 y\n"), "bad.ply", "line 10", "bad number 'y' for y");
  expect_kept(parse_ply(ahead + "1 2\n-inf 4\n3 0 1 1\n", "t.ply"), 2, 1, 0, -INFINITY);
  expect_error(ply(ahead + "1 2\n3 4\n4 0 1 2\n"), "bad.ply", "line 11",
               "list 'vertex_indices' declares 4 items, line has 3");
  expect_error(ply(ahead + "1 2\n3 4\n"), "bad.ply", "line 10", "truncated data: file ends at element 'face' 0 of 1");
  expect_error(ply(ahead + "1 2\n3 4\n3 0 1 1\n9 9\n"), "bad.ply", "line 12", "data after the last element");
  expect_error(
      ply("ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\nproperty float y\nend_header\n1 2\n"),
      "bad.ply", "line 3", "cannot fit");
}

TEST(OutlineIoCorrupt, PlyBinaryErrorsNameTheByte) {
  const std::string head =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string verts = f32s({1, 2, 3, 4});
  std::string cut = head + verts.substr(0, 12);
  expect_error(ply(cut), "bad.ply", "byte " + std::to_string(cut.size()),
               "truncated data: element 'vertex' needs 2 x 8 bytes");
  // Face list of 200 ints where 2 are present.
  std::string face = head + verts + std::string(1, static_cast<char>(200)) + f32s({0, 0});
  expect_error(ply(face), "bad.ply", "byte " + std::to_string(head.size() + 17), "list of 200 items runs past the end");
  std::string no_face = head + verts;
  expect_error(ply(no_face), "bad.ply", "byte " + std::to_string(no_face.size()), "truncated data in element 'face' 0");
  const float inf = std::numeric_limits<float>::infinity();
  expect_kept(parse_ply(head + f32s({1, 2, 3, inf}) + std::string(1, 0), "t.ply"), 2, 1, 1, INFINITY);
  expect_error(ply(head + verts + std::string(1, 0) + "JUNK"), "bad.ply", "byte " + std::to_string(head.size() + 17),
               "4 bytes of unexpected data");
  std::string neg =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property list char int l\nend_header\n";
  expect_error(ply(neg + f32s({1, 2}) + "\xff"), "bad.ply", "byte " + std::to_string(neg.size() + 8), "negative");
}

TEST(OutlineIoCorrupt, TruncatedFixturesAtEveryLength) {
  // Every prefix of every fixture either reads (a shorter but complete text file) or throws ReadError.
  for (const char* name : {"known_binary.pcd", "known_compressed.pcd", "known_binary.ply", "known_ascii.ply",
                           "known_ascii.pcd", "known.csv"}) {
    const std::string full = slurp(name);
    ASSERT_FALSE(full.empty()) << name;
    const std::string n = name;
    const bool binary = n.find("binary") != std::string::npos || n.find("compressed") != std::string::npos;
    for (std::size_t len = 0; len < full.size(); ++len) {
      std::string_view part(full.data(), len);
      try {
        Cloud c = n.ends_with(".pcd")   ? parse_pcd(part, n)
                  : n.ends_with(".ply") ? parse_ply(part, n)
                                        : parse_text_cloud(part, n);
        // A cut binary file is always an error; a cut text file may end at a line boundary.
        EXPECT_FALSE(binary) << n << " read with " << len << " of " << full.size() << " bytes";
        EXPECT_GT(c.size(), 0u);
      } catch (const ReadError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(n + ": ", 0), 0u) << e.what();
      }
    }
  }
}

TEST(OutlineIoCorrupt, RandomGarbageAndBitFlipsOnlyGiveReadErrors) {
  std::mt19937 rng(3);
  const std::string seeds[] = {slurp("known_binary.pcd"), slurp("known_compressed.pcd"), slurp("known_binary.ply"),
                               slurp("known_ascii.ply"),  slurp("known_ascii.pcd"),      slurp("known.xyz")};
  int errors = 0, reads = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const std::string& seed = seeds[trial % 6];
    std::string s = seed;
    for (int k = 0, nk = 1 + static_cast<int>(rng() % 4); k < nk; ++k) s[rng() % s.size()] = static_cast<char>(rng());
    try {
      Cloud c = trial % 6 < 2 || trial % 6 == 4 ? parse_pcd(s, "f.pcd")
                : trial % 6 < 4                 ? parse_ply(s, "f.ply")
                                                : parse_text_cloud(s, "f.xyz");
      EXPECT_GT(c.size(), 0u);
      for (double v : c.xyz) EXPECT_TRUE(std::isfinite(v));
      ++reads;
    } catch (const ReadError&) {
      ++errors;
    }
  }
  EXPECT_GT(errors, 0);
  EXPECT_GT(reads, 0);
}
