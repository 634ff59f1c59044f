// PCD (Point Cloud Library format, v0.7): header lines up to DATA, then ascii lines, binary records
// (array of structs) or binary_compressed (LZF block of the fields one after the other).
// Only x, y and (if present) z are taken, from fields of any SIZE/TYPE/COUNT; other fields are skipped.
#include <algorithm>
#include <cctype>

#include "outline_io/read_common.hpp"

namespace hg::outline_io {

using namespace detail;

void lzf_decompress(std::string_view in, char* out, std::size_t out_size, const std::string& name,
                    std::size_t base_offset) {
  const auto* ip = reinterpret_cast<const unsigned char*>(in.data());
  const auto* const in_begin = ip;
  const auto* const in_end = ip + in.size();
  std::size_t op = 0;
  auto at = [&](const unsigned char* p) { return base_offset + static_cast<std::size_t>(p - in_begin); };
  while (ip < in_end) {
    const unsigned char* run_start = ip;
    unsigned ctrl = *ip++;
    if (ctrl < 32) {  // literal run of ctrl + 1 bytes
      std::size_t len = ctrl + 1;
      if (static_cast<std::size_t>(in_end - ip) < len)
        fail_byte(
            name, at(run_start),
            "truncated data: LZF literal run of " + std::to_string(len) + " bytes runs past the compressed block");
      if (out_size - op < len)
        fail_byte(name, at(run_start),
                  "corrupt LZF data: output would exceed the declared uncompressed size " + std::to_string(out_size));
      std::memcpy(out + op, ip, len);
      ip += len;
      op += len;
    } else {  // back reference: length (ctrl >> 5) + 2, extended by one byte when 7; 13-bit distance + 1
      std::size_t len = ctrl >> 5;
      if (len == 7) {
        if (ip >= in_end) fail_byte(name, at(run_start), "truncated data: LZF back reference cut off");
        len += *ip++;
      }
      if (ip >= in_end) fail_byte(name, at(run_start), "truncated data: LZF back reference cut off");
      std::size_t dist = ((static_cast<std::size_t>(ctrl & 0x1f) << 8) | *ip++) + 1;
      len += 2;
      if (dist > op)
        fail_byte(name, at(run_start),
                  "corrupt LZF data: back reference " + std::to_string(dist) + " bytes before the start of the output");
      if (out_size - op < len)
        fail_byte(name, at(run_start),
                  "corrupt LZF data: output would exceed the declared uncompressed size " + std::to_string(out_size));
      // Byte by byte: source and destination overlap when dist < len (a repeated pattern).
      for (std::size_t k = 0; k < len; ++k, ++op) out[op] = out[op - dist];
    }
  }
  if (op != out_size)
    fail_byte(name, at(in_end),
              "truncated data: LZF block decodes to " + std::to_string(op) + " bytes, header declares " +
                  std::to_string(out_size));
}

namespace {

struct Field {
  std::string name;
  std::uint64_t size = 0, count = 1;
  char type = 0;
  Scalar scalar = Scalar::F32;
  std::uint64_t offset = 0;  // within a binary record
};

bool to_scalar(char type, std::uint64_t size, Scalar& s) {
  switch (type) {
    case 'I':
      s = size == 1 ? Scalar::I8 : size == 2 ? Scalar::I16 : size == 4 ? Scalar::I32 : Scalar::I64;
      return size == 1 || size == 2 || size == 4 || size == 8;
    case 'U':
      s = size == 1 ? Scalar::U8 : size == 2 ? Scalar::U16 : size == 4 ? Scalar::U32 : Scalar::U64;
      return size == 1 || size == 2 || size == 4 || size == 8;
    case 'F': s = size == 4 ? Scalar::F32 : Scalar::F64; return size == 4 || size == 8;
  }
  return false;
}

std::string upper(std::string_view s) {
  std::string r(s);
  for (auto& c : r) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return r;
}

// What the header says, with the line of each keyword for the error messages.
struct Header {
  std::vector<Field> fields;
  bool have_size = false, have_type = false, have_width = false, have_points = false;
  std::uint64_t width = 0, height = 1, points = 0;
  std::size_t size_line = 0, type_line = 0, count_line = 0, points_line = 0, data_line = 0;
  std::string data_kind;
  // Derived by layout(): bytes per point in binary layouts, the field index of x, y, z (-1: absent).
  std::uint64_t record = 0;
  int axis_field[3] = {-1, -1, -1};
  bool has_z() const { return axis_field[2] >= 0; }
};

// One header line's keyword and values (tok[0] is the keyword as written); true at DATA.
bool read_keyword(Header& h, const std::string& key, const std::vector<std::string_view>& tok, std::size_t line_no,
                  const std::string& name) {
  const std::size_t nvals = tok.size() - 1;
  auto need_fields = [&] {
    if (h.fields.empty()) fail_line(name, line_no, "bad header: " + key + " before FIELDS");
    if (nvals != h.fields.size())
      fail_line(name, line_no,
                "bad header: " + key + " has " + std::to_string(nvals) + " values for " +
                    std::to_string(h.fields.size()) + " fields");
  };
  auto u64 = [&](std::size_t i) {
    std::uint64_t v;
    if (!parse_u64(tok[i], v)) fail_line(name, line_no, "bad header: " + key + ": bad number " + quote(tok[i]));
    return v;
  };
  if (key == "VERSION" || key == "VIEWPOINT") {
    return false;
  } else if (key == "FIELDS" || key == "COLUMNS") {
    if (!h.fields.empty()) fail_line(name, line_no, "bad header: FIELDS given twice");
    if (nvals == 0) fail_line(name, line_no, "bad header: FIELDS lists no field");
    for (std::size_t i = 1; i < tok.size(); ++i) {
      Field f;
      f.name = std::string(tok[i]);
      if (f.name != "_" &&
          std::any_of(h.fields.begin(), h.fields.end(), [&](const Field& g) { return g.name == f.name; }))
        fail_line(name, line_no, "bad header: field " + quote(f.name) + " given twice");
      h.fields.push_back(std::move(f));
    }
  } else if (key == "SIZE") {
    need_fields();
    for (std::size_t i = 0; i < nvals; ++i) h.fields[i].size = u64(i + 1);
    h.have_size = true;
    h.size_line = line_no;
  } else if (key == "TYPE") {
    need_fields();
    for (std::size_t i = 0; i < nvals; ++i) {
      if (tok[i + 1].size() != 1 || std::string_view("IUF").find(tok[i + 1][0]) == std::string_view::npos)
        fail_line(name, line_no, "bad header: TYPE " + quote(tok[i + 1]) + " (expected I, U or F)");
      h.fields[i].type = tok[i + 1][0];
    }
    h.have_type = true;
    h.type_line = line_no;
  } else if (key == "COUNT") {
    need_fields();
    for (std::size_t i = 0; i < nvals; ++i) {
      h.fields[i].count = u64(i + 1);
      if (h.fields[i].count == 0) fail_line(name, line_no, "bad header: COUNT 0 for field " + quote(h.fields[i].name));
    }
    h.count_line = line_no;
  } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
    if (nvals != 1) fail_line(name, line_no, "bad header: " + key + " needs one value");
    std::uint64_t v = u64(1);
    if (key == "WIDTH") h.width = v, h.have_width = true;
    else if (key == "HEIGHT")
      h.height = v;
    else
      h.points = v, h.have_points = true, h.points_line = line_no;
  } else if (key == "DATA") {
    if (nvals != 1) fail_line(name, line_no, "bad header: DATA needs one value (ascii, binary or binary_compressed)");
    h.data_kind = std::string(tok[1]);
    h.data_line = line_no;
    return true;
  } else {
    fail_line(name, line_no, "bad header: unknown keyword " + quote(tok[0]));
  }
  return false;
}

// The header lines up to and including DATA; the cursor is left at the first data byte.
Header read_header(LineCursor& cur, const std::string& name) {
  Header h;
  std::string_view line;
  std::vector<std::string_view> tok;
  while (true) {
    if (!cur.next(line)) fail_line(name, cur.line_no, "bad header: file ends before the DATA line");
    if (line.find('\0') != std::string_view::npos)
      fail_line(name, cur.line_no, "bad header: binary bytes in a header line (not a PCD file?)");
    std::string_view t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    split_blanks(t, tok);
    if (read_keyword(h, upper(tok[0]), tok, cur.line_no, name)) return h;
  }
}

// Checks the header as a whole and derives the record layout and the axis fields.
void layout(Header& h, const std::string& name) {
  const std::size_t data_line = h.data_line;
  if (h.data_kind != "ascii" && h.data_kind != "binary" && h.data_kind != "binary_compressed")
    fail_line(name, data_line,
              "unsupported format: DATA " + quote(h.data_kind) + " (expected ascii, binary or binary_compressed)");
  if (h.fields.empty()) fail_line(name, data_line, "bad header: no FIELDS line");
  if (!h.have_size) fail_line(name, data_line, "bad header: no SIZE line");
  if (!h.have_type) fail_line(name, data_line, "bad header: no TYPE line");
  if (!h.have_width) fail_line(name, data_line, "bad header: no WIDTH line");
  // COUNT defaults to 1 per field, HEIGHT to 1.
  std::uint64_t wh;
  if (!mul_ok(h.width, h.height, wh)) fail_line(name, data_line, "wrong counts: WIDTH x HEIGHT overflows");
  if (!h.have_points) h.points = wh;
  else if (h.points != wh)
    fail_line(name, h.points_line,
              "wrong counts: POINTS " + std::to_string(h.points) + " but WIDTH x HEIGHT = " + std::to_string(h.width) +
                  " x " + std::to_string(h.height) + " = " + std::to_string(wh));

  for (std::size_t i = 0; i < h.fields.size(); ++i) {
    Field& f = h.fields[i];
    if (!to_scalar(f.type, f.size, f.scalar))
      fail_line(name, h.type_line > h.size_line ? h.type_line : h.size_line,
                "bad header: field " + quote(f.name) + " has TYPE " + std::string(1, f.type) + " with SIZE " +
                    std::to_string(f.size));
    f.offset = h.record;
    std::uint64_t bytes;
    if (!mul_ok(f.size, f.count, bytes) || !add_ok(h.record, bytes, h.record))
      fail_line(name, h.count_line ? h.count_line : h.size_line, "bad header: record size overflows");
    for (int k = 0; k < 3; ++k)
      if (f.name == axis_name(k)) h.axis_field[k] = static_cast<int>(i);
  }
  if (h.axis_field[0] < 0 || h.axis_field[1] < 0) fail_line(name, data_line, "bad header: FIELDS has no x and y");
  if (h.points == 0) fail_line(name, data_line, "no points in file (POINTS 0)");
}

// ascii: one line of FIELDS/COUNT values per point.
void read_ascii(const Header& h, LineCursor& cur, std::size_t remaining, const std::string& name, Cloud& cloud) {
  std::uint64_t tokens_per_point = 0;
  for (auto& f : h.fields)
    if (!add_ok(tokens_per_point, f.count, tokens_per_point))
      fail_line(name, h.count_line, "bad header: COUNT total overflows");
  // Each point takes at least 2 bytes per value: caps the reservation; a header that claims more
  // points than the file holds ends in the "truncated data" error below, nothing absurd is allocated.
  cloud.xyz.reserve(
      3 * std::min<std::uint64_t>(h.points, remaining / (2 * std::min<std::uint64_t>(tokens_per_point, 1u << 30)) + 1));
  // Token index of each axis in a line.
  std::uint64_t axis_tok[3] = {0, 0, 0};
  for (std::uint64_t i = 0, t = 0; i < h.fields.size(); t += h.fields[i].count, ++i)
    for (int k = 0; k < 3; ++k)
      if (h.axis_field[k] == static_cast<int>(i)) axis_tok[k] = t;
  std::string_view line;
  std::vector<std::string_view> tok;
  std::uint64_t n = 0;
  while (cur.next(line)) {
    split_blanks(line, tok);
    if (tok.empty()) continue;
    if (n == h.points)
      fail_line(name, cur.line_no,
                "wrong counts: more data lines than the " + std::to_string(h.points) + " points declared");
    if (tok.size() != tokens_per_point)
      fail_line(name, cur.line_no,
                "wrong number of values: " + std::to_string(tok.size()) + " (FIELDS/COUNT declare " +
                    std::to_string(tokens_per_point) + ")");
    double v[3] = {0, 0, 0};
    for (int k = 0; k < (h.has_z() ? 3 : 2); ++k) {
      std::string_view s = tok[axis_tok[k]];
      switch (parse_number(s, v[k])) {
        case Num::Ok:
        case Num::NonFinite: break;  // NaN: a no-return pixel, kept and counted
        case Num::Bad: fail_line(name, cur.line_no, std::string("bad number ") + quote(s) + " for " + axis_name(k));
        case Num::Range:
          fail_line(name, cur.line_no, std::string("number out of range ") + quote(s) + " for " + axis_name(k));
      }
    }
    cloud.xyz.insert(cloud.xyz.end(), v, v + 3);
    ++n;
  }
  if (n != h.points)
    fail_line(name, cur.line_no,
              "truncated data: " + std::to_string(n) + " points found, header declares " + std::to_string(h.points));
}

// binary_compressed: two size words, then one LZF block of the fields one after the other (decompressed
// into `out`). Every count is checked against the bytes present before anything is allocated.
void decompress_block(const Header& h, std::string_view data, std::size_t data_start, std::uint64_t data_bytes,
                      const std::string& name, std::string& out) {
  const std::size_t remaining = data.size() - data_start;
  if (remaining < 8) fail_byte(name, data.size(), "truncated data: binary_compressed size words missing");
  const std::uint32_t csize = load<std::uint32_t>(data.data() + data_start);
  const std::uint32_t usize = load<std::uint32_t>(data.data() + data_start + 4);
  if (usize != data_bytes)
    fail_byte(name, data_start + 4,
              "wrong counts: uncompressed size " + std::to_string(usize) + " but " + std::to_string(h.points) +
                  " points of " + std::to_string(h.record) + " bytes need " + std::to_string(data_bytes));
  if (csize > remaining - 8)
    fail_byte(name, data.size(),
              "truncated data: compressed block of " + std::to_string(csize) + " bytes from byte " +
                  std::to_string(data_start + 8) + ", file has " + std::to_string(remaining - 8));
  // An LZF back reference emits at most 264 bytes from 3 input bytes: a larger ratio is a lie.
  if (static_cast<std::uint64_t>(usize) > static_cast<std::uint64_t>(csize) * 88 + 88)
    fail_byte(name, data_start + 4,
              "wrong counts: uncompressed size " + std::to_string(usize) + " impossible from " + std::to_string(csize) +
                  " compressed bytes");
  if (remaining - 8 > csize) {
    // PCL may pad the file after the block; anything but zero padding means the sizes are wrong.
    std::string_view tail = data.substr(data_start + 8 + csize);
    if (tail.find_first_not_of('\0') != std::string_view::npos)
      fail_byte(
          name, data_start + 8 + csize,
          "wrong counts: " + std::to_string(tail.size()) + " bytes of unexpected data after the compressed block");
  }
  out.resize(usize);
  lzf_decompress(data.substr(data_start + 8, csize), out.data(), usize, name, data_start + 8);
}

// binary (records, array of structs) or binary_compressed (field blocks, struct of arrays).
void read_binary(const Header& h, std::string_view data, std::size_t data_start, const std::string& name,
                 Cloud& cloud) {
  const std::size_t remaining = data.size() - data_start;
  const std::uint64_t points = h.points, record = h.record;
  std::uint64_t data_bytes;
  if (record == 0 || !mul_ok(points, record, data_bytes))
    fail_line(name, h.points_line ? h.points_line : h.data_line, "wrong counts: POINTS x record size overflows");
  std::string decompressed;
  const char* base = nullptr;
  const bool soa = h.data_kind != "binary";
  if (!soa) {
    if (data_bytes > remaining)
      fail_byte(name, data.size(),
                "truncated data: " + std::to_string(points) + " points of " + std::to_string(record) + " bytes need " +
                    std::to_string(data_bytes) + " bytes from byte " + std::to_string(data_start) + ", file has " +
                    std::to_string(remaining));
    if (data_bytes < remaining)
      fail_byte(name, data_start + data_bytes,
                "wrong counts: " + std::to_string(remaining - data_bytes) + " bytes of unexpected data after the " +
                    std::to_string(points) + " points declared");
    base = data.data() + data_start;
  } else {
    decompress_block(h, data, data_start, data_bytes, name, decompressed);
    base = decompressed.data();
  }
  cloud.xyz.resize(3 * points);
  for (int k = 0; k < (h.has_z() ? 3 : 2); ++k) {
    const Field& f = h.fields[h.axis_field[k]];
    // AoS: record i at i * record; SoA: field block at points * offset, element stride size * count.
    const std::uint64_t start = soa ? points * f.offset : f.offset;
    const std::uint64_t stride = soa ? f.size * f.count : record;
    for (std::uint64_t i = 0; i < points; ++i) cloud.xyz[3 * i + k] = load_scalar(f.scalar, base + start + i * stride);
  }
}

}  // namespace

Cloud parse_pcd(std::string_view data, const std::string& name) {
  LineCursor cur{data};
  Header h = read_header(cur, name);
  layout(h, name);
  Cloud cloud;
  cloud.has_z = h.has_z();
  cloud.format = "pcd " + h.data_kind;
  if (h.data_kind == "ascii") read_ascii(h, cur, data.size() - cur.pos, name, cloud);
  else
    read_binary(h, data, cur.pos, name, cloud);
  return count_nonfinite(cloud);
}

}  // namespace hg::outline_io
