// Readers against independent expectations: hand-written fixtures with known points, binary fixtures
// from tests/data/outline_io/make_fixtures.py (Python struct), and random layouts written here by a
// small writer of our own (with its own LZF compressor for binary_compressed).
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "lzf_test_compressor.hpp"
#include "outline_io/cloud.hpp"

using namespace hg::outline_io;

namespace {

using P3 = std::array<double, 3>;
const std::vector<P3> kKnown = {{0, 0, 1}, {10, 0, 1}, {10, 10, 1.5}, {0, 10, 2}, {5, 2.5, -3}, {2, 8, 0.25}};

std::string data(const std::string& name) { return std::string(HG_TEST_DATA) + "/outline_io/" + name; }

void expect_cloud(const Cloud& c, const std::vector<P3>& want, bool has_z) {
  ASSERT_EQ(c.size(), want.size());
  EXPECT_EQ(c.has_z, has_z);
  for (std::size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(c.xyz[3 * i], want[i][0]) << "point " << i;
    EXPECT_EQ(c.xyz[3 * i + 1], want[i][1]) << "point " << i;
    EXPECT_EQ(c.xyz[3 * i + 2], has_z ? want[i][2] : 0.0) << "point " << i;
  }
}

}  // namespace

TEST(OutlineIoText, KnownXyzWithCommentsTabsAndSigns) {
  Cloud c = read_cloud_file(data("known.xyz"));
  expect_cloud(c, kKnown, true);
  EXPECT_EQ(c.format, "xyz");
}

TEST(OutlineIoText, KnownCsvWithHeaderCommasAndCrlf) { expect_cloud(read_cloud_file(data("known.csv")), kKnown, true); }

TEST(OutlineIoText, TwoColumnsMeansNoZ) { expect_cloud(read_cloud_file(data("known_2d.txt")), kKnown, false); }

TEST(OutlineIoText, ColumnsAfterTheThirdAreIgnored) {
  Cloud c = parse_text_cloud("1 2 3 255 0 0\n4,5,6,0,255,0\n", "mem.xyz");
  expect_cloud(c, {{1, 2, 3}, {4, 5, 6}}, true);
}

TEST(OutlineIoText, NoTrailingNewlineAndBom) {
  Cloud c = parse_text_cloud("\xEF\xBB\xBFx y\n1e-3 -2.5E+2", "mem.txt");
  expect_cloud(c, {{0.001, -250, 0}}, false);
}

TEST(OutlineIoPcd, AsciiOrganizedWithSkippedFieldsAndCounts) {
  Cloud c = read_cloud_file(data("known_ascii.pcd"));
  expect_cloud(c, kKnown, true);
  EXPECT_EQ(c.format, "pcd ascii");
}

TEST(OutlineIoPcd, BinaryFixtureWithNanInSkippedField) {
  Cloud c = read_cloud_file(data("known_binary.pcd"));
  expect_cloud(c, kKnown, true);
  EXPECT_EQ(c.format, "pcd binary");
}

TEST(OutlineIoPcd, CompressedFixtureOfLiteralRuns) {
  Cloud c = read_cloud_file(data("known_compressed.pcd"));
  expect_cloud(c, kKnown, true);
  EXPECT_EQ(c.format, "pcd binary_compressed");
}

TEST(OutlineIoPly, AsciiWithColoursAndFaces) {
  Cloud c = read_cloud_file(data("known_ascii.ply"));
  expect_cloud(c, kKnown, true);
  EXPECT_EQ(c.format, "ply ascii");
}

TEST(OutlineIoPly, BinaryWithListsAndElementsBeforeAndAfter) {
  // make_fixtures.py stores z as int: whole part of KNOWN's z.
  std::vector<P3> want = kKnown;
  for (auto& p : want) p[2] = static_cast<double>(static_cast<int>(p[2]));
  Cloud c = read_cloud_file(data("known_binary.ply"));
  expect_cloud(c, want, true);
  EXPECT_EQ(c.format, "ply binary_little_endian");
}

TEST(OutlineIoFormat, ExtensionChoosesTheReaderCaseInsensitively) {
  EXPECT_EQ(format_from_path("a/b.XYZ"), Format::Text);
  EXPECT_EQ(format_from_path("b.Csv"), Format::Text);
  EXPECT_EQ(format_from_path("b.txt"), Format::Text);
  EXPECT_EQ(format_from_path("b.PCD"), Format::Pcd);
  EXPECT_EQ(format_from_path("b.ply"), Format::Ply);
  EXPECT_THROW(format_from_path("b.las"), ReadError);
  EXPECT_THROW(format_from_path("dir.d/noext"), ReadError);
}

TEST(OutlineIoLzf, HandAssembledLiteralAndOverlappingBackReference) {
  // "abc" as a literal run, then 9 bytes from 3 back (overlapping copy): length 9 -> 7 + ext 0, distance 3 -> 2.
  const std::string block = std::string(
                                "\x02"
                                "abc",
                                4) +
                            std::string("\xE0\x00\x02", 3) +
                            std::string(
                                "\x00"
                                "!",
                                2);
  std::string out(13, '\0');
  lzf_decompress(block, out.data(), out.size(), "mem", 0);
  EXPECT_EQ(out, "abcabcabcabc!");
  // Short form: length 4 -> ctrl (2 << 5), distance 1 -> 0: "x" then "xxxx".
  const std::string block2 = std::string("\x00x", 2) + std::string("\x40\x00", 2);
  std::string out2(5, '\0');
  lzf_decompress(block2, out2.data(), out2.size(), "mem", 0);
  EXPECT_EQ(out2, "xxxxx");
}

TEST(OutlineIoLzf, RoundTripThroughTheTestCompressor) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    std::string raw;
    const int n = 1 + static_cast<int>(rng() % 20000);
    while (static_cast<int>(raw.size()) < n) {
      if (rng() % 3 == 0 && raw.size() > 10) {  // repeat an earlier piece: creates back references
        std::size_t from = rng() % raw.size(), len = 1 + rng() % 300;
        for (std::size_t k = 0; k < len; ++k) raw += raw[from + k];  // may overlap itself, on purpose
      } else {
        raw += static_cast<char>(rng() % (trial % 2 ? 4 : 256));
      }
    }
    std::string comp = hg_test::lzf_compress(raw);
    std::string out(raw.size(), '\0');
    lzf_decompress(comp, out.data(), out.size(), "mem", 0);
    ASSERT_EQ(out, raw) << "trial " << trial;
  }
}

// ---- random layouts written by a test-side writer ----
namespace {

struct TestType {
  char pcd;  // I U F
  int size;
  const char* ply;
};
const TestType kTypes[] = {{'I', 1, "char"},  {'U', 1, "uchar"},  {'I', 2, "short"}, {'U', 2, "ushort"},
                           {'I', 4, "int"},   {'U', 4, "uint32"}, {'F', 4, "float"}, {'F', 8, "float64"},
                           {'I', 8, nullptr}, {'U', 8, nullptr}};

void put(std::string& s, const TestType& t, double v) {
  char b[8];
  switch (t.pcd) {
    case 'F':
      if (t.size == 4) {
        float f = static_cast<float>(v);
        std::memcpy(b, &f, 4);
      } else
        std::memcpy(b, &v, 8);
      break;
    case 'I': {
      long long i = static_cast<long long>(v);
      std::memcpy(b, &i, t.size);
      break;
    }  // little endian: low bytes first
    default: {
      unsigned long long u = static_cast<unsigned long long>(v);
      std::memcpy(b, &u, t.size);
    }
  }
  s.append(b, t.size);
}

// A value every type can hold exactly: whole numbers in [lo, hi], quarters for floats.
double value_for(const TestType& t, std::mt19937& rng) {
  int lo = t.pcd == 'U' ? 0 : -100, hi = 100;
  double v = lo + static_cast<int>(rng() % (hi - lo + 1));
  if (t.pcd == 'F') v += 0.25 * (rng() % 4);
  return v;
}

std::string text_of(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

struct Column {
  std::string name;
  TestType type;
  int count;
};

}  // namespace

TEST(OutlineIoPcd, RandomLayoutsInAllThreeEncodings) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 60; ++trial) {
    const bool has_z = trial % 3 != 0;
    std::vector<Column> cols;
    for (int a = 0; a < (has_z ? 3 : 2); ++a) cols.push_back({std::string(1, "xyz"[a]), kTypes[rng() % 10], 1});
    const int extras = static_cast<int>(rng() % 4);
    for (int e = 0; e < extras; ++e) {
      Column c{e % 2 ? "_" : "extra" + std::to_string(e), kTypes[rng() % 10], 1 + static_cast<int>(rng() % 4)};
      cols.insert(cols.begin() + rng() % (cols.size() + 1), c);
    }
    const std::size_t n = 1 + rng() % 300, width = (n % 2 == 0) ? n / 2 : n, height = n / width;
    std::vector<std::vector<std::vector<double>>> vals(cols.size());  // [column][point][k]
    std::vector<P3> want(n, P3{0, 0, 0});
    for (std::size_t c = 0; c < cols.size(); ++c) {
      vals[c].resize(n);
      for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < cols[c].count; ++k) {
          double v = value_for(cols[c].type, rng);
          vals[c][i].push_back(v);
          for (int a = 0; a < 3; ++a)
            if (cols[c].name == std::string(1, "xyz"[a])) want[i][a] = v;
        }
    }
    std::string head = "# random layout\nVERSION 0.7\nFIELDS";
    for (auto& c : cols) head += " " + c.name;
    head += "\nSIZE";
    for (auto& c : cols) head += " " + std::to_string(c.type.size);
    head += "\nTYPE";
    for (auto& c : cols) head += std::string(" ") + c.type.pcd;
    head += "\nCOUNT";
    for (auto& c : cols) head += " " + std::to_string(c.count);
    head += "\nWIDTH " + std::to_string(width) + "\nHEIGHT " + std::to_string(height) +
            "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(n) + "\n";

    std::string ascii = head + "DATA ascii\n";
    std::string binary = head + "DATA binary\n";
    std::string soa;
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t c = 0; c < cols.size(); ++c)
        for (double v : vals[c][i]) {
          ascii += text_of(v) + " ";
          put(binary, cols[c].type, v);
        }
      ascii += "\n";
    }
    for (std::size_t c = 0; c < cols.size(); ++c)
      for (std::size_t i = 0; i < n; ++i)
        for (double v : vals[c][i]) put(soa, cols[c].type, v);
    std::string comp = hg_test::lzf_compress(soa);
    std::string compressed = head + "DATA binary_compressed\n";
    std::uint32_t sizes[2] = {static_cast<std::uint32_t>(comp.size()), static_cast<std::uint32_t>(soa.size())};
    compressed.append(reinterpret_cast<const char*>(sizes), 8);
    compressed += comp;

    SCOPED_TRACE("trial " + std::to_string(trial) + "\n" + head);
    expect_cloud(parse_pcd(ascii, "a.pcd"), want, has_z);
    expect_cloud(parse_pcd(binary, "b.pcd"), want, has_z);
    expect_cloud(parse_pcd(compressed, "c.pcd"), want, has_z);
  }
}

TEST(OutlineIoPly, RandomLayoutsAsciiAndBinary) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 60; ++trial) {
    const bool has_z = trial % 4 != 0;
    // Vertex properties: x y [z] of random types among others; a list property sometimes.
    struct Prop {
      std::string name;
      TestType type;
      bool list;
    };
    std::vector<Prop> props;
    for (int a = 0; a < (has_z ? 3 : 2); ++a) props.push_back({std::string(1, "xyz"[a]), kTypes[rng() % 8], false});
    for (int e = 0, ne = static_cast<int>(rng() % 4); e < ne; ++e)
      props.insert(props.begin() + rng() % (props.size() + 1),
                   Prop{"p" + std::to_string(e), kTypes[rng() % 8], rng() % 3 == 0});
    const std::size_t n = 1 + rng() % 200, faces = rng() % 50;
    const bool before = rng() % 2;
    std::string head = "ply\nformat FORMAT 1.0\ncomment random layout\n";
    if (before) head += "element material 2\nproperty uchar id\nproperty list uint16 float coeffs\n";
    head += "element vertex " + std::to_string(n) + "\n";
    for (auto& p : props)
      head += p.list ? "property list uchar " + std::string(p.type.ply) + " " + p.name + "\n"
                     : "property " + std::string(p.type.ply) + " " + p.name + "\n";
    head += "element face " + std::to_string(faces) +
            "\nproperty list uchar int vertex_indices\nelement empty 5\nend_header\n";
    std::string ascii, binary;
    const TestType u8 = kTypes[1], u16 = kTypes[3], f32 = kTypes[6], i32 = kTypes[4];
    if (before)
      for (int m = 0; m < 2; ++m) {
        int k = static_cast<int>(rng() % 5);
        ascii += std::to_string(m) + " " + std::to_string(k);
        put(binary, u8, m);
        put(binary, u16, k);
        for (int q = 0; q < k; ++q) ascii += " 0.5", put(binary, f32, 0.5);
        ascii += "\n";
      }
    std::vector<P3> want(n, P3{0, 0, 0});
    for (std::size_t i = 0; i < n; ++i) {
      for (auto& p : props) {
        if (p.list) {
          int k = static_cast<int>(rng() % 4);
          ascii += std::to_string(k) + " ";
          put(binary, u8, k);
          for (int q = 0; q < k; ++q) {
            double v = value_for(p.type, rng);
            ascii += text_of(v) + " ";
            put(binary, p.type, v);
          }
          continue;
        }
        double v = value_for(p.type, rng);
        for (int a = 0; a < 3; ++a)
          if (p.name == std::string(1, "xyz"[a])) want[i][a] = v;
        ascii += text_of(v) + " ";
        put(binary, p.type, v);
      }
      ascii += "\n";
    }
    for (std::size_t f = 0; f < faces; ++f) {
      int k = 3 + static_cast<int>(rng() % 3);
      ascii += std::to_string(k);
      put(binary, u8, k);
      for (int q = 0; q < k; ++q) {
        int idx = static_cast<int>(rng() % n);
        ascii += " " + std::to_string(idx);
        put(binary, i32, idx);
      }
      ascii += "\n";
    }
    auto with_format = [&](const std::string& fmt) {
      std::string h = head;
      h.replace(h.find("FORMAT"), 6, fmt);
      return h;
    };
    SCOPED_TRACE("trial " + std::to_string(trial) + "\n" + head);
    expect_cloud(parse_ply(with_format("ascii") + ascii, "a.ply"), want, has_z);
    expect_cloud(parse_ply(with_format("binary_little_endian") + binary, "b.ply"), want, has_z);
  }
}
