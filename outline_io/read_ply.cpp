// PLY (Stanford polygon format): ascii or binary_little_endian. The "vertex" element gives x, y [, z]
// of any numeric type; every other property and element (faces with their lists, edges, ...) is walked
// over and checked for length but not kept. Ascii data: one element instance per line.
#include <algorithm>

#include "outline_io/read_common.hpp"

namespace hg::outline_io {

using namespace detail;

namespace {

struct Property {
  std::string name;
  bool is_list = false;
  Scalar type = Scalar::F32;       // scalar type, or the item type of a list
  Scalar count_type = Scalar::U8;  // list length type
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> props;
  std::size_t header_line = 0;
};

bool parse_type(std::string_view s, Scalar& t) {
  static const std::pair<std::string_view, Scalar> names[] = {
      {"char", Scalar::I8},   {"int8", Scalar::I8},     {"uchar", Scalar::U8},   {"uint8", Scalar::U8},
      {"short", Scalar::I16}, {"int16", Scalar::I16},   {"ushort", Scalar::U16}, {"uint16", Scalar::U16},
      {"int", Scalar::I32},   {"int32", Scalar::I32},   {"uint", Scalar::U32},   {"uint32", Scalar::U32},
      {"float", Scalar::F32}, {"float32", Scalar::F32}, {"double", Scalar::F64}, {"float64", Scalar::F64}};
  for (auto& [n, v] : names)
    if (s == n) {
      t = v;
      return true;
    }
  return false;
}

// What the header says, and where x, y, z are.
struct Header {
  std::string format;
  std::vector<Element> elements;
  std::size_t end_line = 0;  // the line of end_header
  int vertex_elem = -1;
  int axis_prop[3] = {-1, -1, -1};
  int naxes() const { return axis_prop[2] >= 0 ? 3 : 2; }
  const Element& vertex() const { return elements[vertex_elem]; }
};

// "property TYPE NAME" or "property list TYPE TYPE NAME".
Property read_property(const std::vector<std::string_view>& tok, std::size_t line_no, const std::string& name) {
  Property p;
  if (tok.size() == 5 && tok[1] == "list") {
    p.is_list = true;
    if (!parse_type(tok[2], p.count_type) || scalar_is_float(p.count_type))
      fail_line(name, line_no, "bad header: list length type " + quote(tok[2]) + " (an integer type is needed)");
    if (!parse_type(tok[3], p.type)) fail_line(name, line_no, "bad header: unknown type " + quote(tok[3]));
    p.name = std::string(tok[4]);
  } else if (tok.size() == 3) {
    if (!parse_type(tok[1], p.type)) fail_line(name, line_no, "bad header: unknown type " + quote(tok[1]));
    p.name = std::string(tok[2]);
  } else {
    fail_line(name, line_no,
              "bad header: property line must be 'property TYPE NAME' or 'property list TYPE TYPE NAME'");
  }
  return p;
}

// The header lines after "ply" up to end_header; the cursor is left at the first data byte.
Header read_header(LineCursor& cur, const std::string& name) {
  Header h;
  std::string_view line;
  std::vector<std::string_view> tok;
  while (true) {
    if (!cur.next(line)) fail_line(name, cur.line_no, "bad header: file ends before end_header");
    if (line.find('\0') != std::string_view::npos)
      fail_line(name, cur.line_no, "bad header: binary bytes in a header line");
    split_blanks(line, tok);
    if (tok.empty()) continue;
    if (tok[0] == "end_header") break;
    if (tok[0] == "comment" || tok[0] == "obj_info") continue;
    if (tok[0] == "format") {
      if (tok.size() != 3) fail_line(name, cur.line_no, "bad header: format line needs a format and a version");
      h.format = std::string(tok[1]);
      if (h.format != "ascii" && h.format != "binary_little_endian")
        fail_line(name, cur.line_no,
                  "unsupported format " + quote(h.format) + " (ascii and binary_little_endian are read)");
    } else if (tok[0] == "element") {
      Element e;
      if (tok.size() != 3 || !parse_u64(tok[2], e.count))
        fail_line(name, cur.line_no, "bad header: element line must be 'element NAME COUNT'");
      e.name = std::string(tok[1]);
      e.header_line = cur.line_no;
      h.elements.push_back(std::move(e));
    } else if (tok[0] == "property") {
      if (h.elements.empty()) fail_line(name, cur.line_no, "bad header: property before any element");
      h.elements.back().props.push_back(read_property(tok, cur.line_no, name));
    } else {
      fail_line(name, cur.line_no, "bad header: unknown keyword " + quote(tok[0]));
    }
  }
  h.end_line = cur.line_no;
  if (h.format.empty()) fail_line(name, h.end_line, "bad header: no format line");
  return h;
}

// The one vertex element and its x, y [, z] properties (scalars, each once).
void find_vertex(Header& h, const std::string& name) {
  for (std::size_t e = 0; e < h.elements.size(); ++e) {
    const Element& el = h.elements[e];
    if (el.name != "vertex") continue;
    if (h.vertex_elem >= 0) fail_line(name, el.header_line, "bad header: second vertex element");
    h.vertex_elem = static_cast<int>(e);
    for (std::size_t p = 0; p < el.props.size(); ++p)
      for (int k = 0; k < 3; ++k)
        if (el.props[p].name == axis_name(k)) {
          if (h.axis_prop[k] >= 0)
            fail_line(name, el.header_line,
                      std::string("bad header: vertex property ") + axis_name(k) + " given twice");
          if (el.props[p].is_list)
            fail_line(name, el.header_line, std::string("bad header: vertex property ") + axis_name(k) + " is a list");
          h.axis_prop[k] = static_cast<int>(p);
        }
  }
  if (h.vertex_elem < 0) fail_line(name, h.end_line, "bad header: no vertex element");
  if (h.axis_prop[0] < 0 || h.axis_prop[1] < 0)
    fail_line(name, h.vertex().header_line, "bad header: vertex element has no x and y properties");
  if (h.vertex().count == 0) fail_line(name, h.vertex().header_line, "no points in file (vertex count 0)");
}

// A binary element without lists: count fixed-size records from `pos` (advanced past them).
void read_binary_records(const Header& h, std::size_t e, std::string_view data, std::size_t& pos,
                         const std::string& name, Cloud& cloud) {
  const Element& el = h.elements[e];
  std::uint64_t rec = 0;
  for (auto& p : el.props) rec += scalar_size(p.type);
  std::uint64_t bytes;
  if (!mul_ok(rec, el.count, bytes) || bytes > data.size() - pos)
    fail_byte(name, data.size(),
              "truncated data: element " + quote(el.name) + " needs " + std::to_string(el.count) + " x " +
                  std::to_string(rec) + " bytes from byte " + std::to_string(pos) + ", file has " +
                  std::to_string(data.size() - pos));
  if (static_cast<int>(e) == h.vertex_elem) {
    std::uint64_t off[3] = {0, 0, 0};
    for (int k = 0; k < h.naxes(); ++k)
      for (int p = 0; p < h.axis_prop[k]; ++p) off[k] += scalar_size(el.props[p].type);
    for (std::uint64_t i = 0; i < el.count; ++i)
      for (int k = 0; k < h.naxes(); ++k)
        cloud.xyz[3 * i + k] = load_scalar(el.props[h.axis_prop[k]].type, data.data() + pos + i * rec + off[k]);
  }
  pos += bytes;
}

// A binary element with lists: instance by instance; each takes at least one byte (the list length).
void read_binary_instances(const Header& h, std::size_t e, std::string_view data, std::size_t& pos,
                           const std::string& name, Cloud& cloud) {
  const Element& el = h.elements[e];
  for (std::uint64_t i = 0; i < el.count; ++i) {
    for (std::size_t p = 0; p < el.props.size(); ++p) {
      const Property& pr = el.props[p];
      auto where = [&] {
        return "element " + quote(el.name) + " " + std::to_string(i) + ", property " + quote(pr.name);
      };
      if (!pr.is_list) {
        const std::size_t sz = scalar_size(pr.type);
        if (data.size() - pos < sz) fail_byte(name, pos, "truncated data in " + where());
        if (static_cast<int>(e) == h.vertex_elem)
          for (int k = 0; k < h.naxes(); ++k)
            if (h.axis_prop[k] == static_cast<int>(p)) cloud.xyz[3 * i + k] = load_scalar(pr.type, data.data() + pos);
        pos += sz;
        continue;
      }
      const std::size_t csz = scalar_size(pr.count_type);
      if (data.size() - pos < csz) fail_byte(name, pos, "truncated data in " + where() + " (list length)");
      bool ok;
      std::uint64_t n = load_count(pr.count_type, data.data() + pos, ok);
      if (!ok) fail_byte(name, pos, "bad list length (negative) in " + where());
      pos += csz;
      std::uint64_t bytes;
      if (!mul_ok(n, scalar_size(pr.type), bytes) || bytes > data.size() - pos)
        fail_byte(
            name, pos,
            "truncated data in " + where() + ": list of " + std::to_string(n) + " items runs past the end of the file");
      pos += bytes;
    }
  }
}

void read_binary(const Header& h, std::string_view data, std::size_t data_start, const std::string& name,
                 Cloud& cloud) {
  const std::size_t remaining = data.size() - data_start;
  const std::uint64_t nvert = h.vertex().count;
  // Bounds the reservation: a vertex takes at least one byte per property.
  if (nvert > remaining / std::max<std::size_t>(1, h.vertex().props.size()))
    fail_line(name, h.vertex().header_line,
              "wrong counts: " + std::to_string(nvert) + " vertices cannot fit in the " + std::to_string(remaining) +
                  " bytes after the header");
  cloud.xyz.resize(3 * nvert);
  std::size_t pos = data_start;
  for (std::size_t e = 0; e < h.elements.size(); ++e) {
    const Element& el = h.elements[e];
    if (el.props.empty()) continue;  // nothing stored per instance
    if (std::none_of(el.props.begin(), el.props.end(), [](const Property& p) { return p.is_list; }))
      read_binary_records(h, e, data, pos, name, cloud);
    else
      read_binary_instances(h, e, data, pos, name, cloud);
  }
  if (pos != data.size())
    fail_byte(
        name, pos,
        "wrong counts: " + std::to_string(data.size() - pos) + " bytes of unexpected data after the last element");
}

// Instance i of element e on one ascii line (tokens `tok`), its x, y [, z] stored when it is a vertex.
void read_ascii_instance(const Header& h, std::size_t e, std::uint64_t i, const std::vector<std::string_view>& tok,
                         std::size_t line_no, const std::string& name, Cloud& cloud) {
  const Element& el = h.elements[e];
  std::size_t t = 0;
  for (std::size_t p = 0; p < el.props.size(); ++p) {
    const Property& pr = el.props[p];
    if (t >= tok.size())
      fail_line(name, line_no,
                "wrong number of values: element " + quote(el.name) + " line ends before property " + quote(pr.name));
    if (pr.is_list) {
      std::uint64_t n;
      if (!parse_u64(tok[t], n))
        fail_line(name, line_no, "bad list length " + quote(tok[t]) + " for property " + quote(pr.name));
      ++t;
      if (n > tok.size() - t)
        fail_line(name, line_no,
                  "wrong number of values: list " + quote(pr.name) + " declares " + std::to_string(n) +
                      " items, line has " + std::to_string(tok.size() - t));
      t += n;
      continue;
    }
    if (static_cast<int>(e) == h.vertex_elem)
      for (int k = 0; k < h.naxes(); ++k)
        if (h.axis_prop[k] == static_cast<int>(p)) {
          double v;
          switch (parse_number(tok[t], v)) {
            case Num::Ok:
            case Num::NonFinite: break;  // a NaN/Inf vertex is kept and counted
            case Num::Bad:
              fail_line(name, line_no, std::string("bad number ") + quote(tok[t]) + " for " + axis_name(k));
            case Num::Range:
              fail_line(name, line_no, std::string("number out of range ") + quote(tok[t]) + " for " + axis_name(k));
          }
          cloud.xyz[3 * i + k] = v;
        }
    ++t;
  }
  if (t != tok.size())
    fail_line(name, line_no,
              "wrong number of values: " + std::to_string(tok.size()) + " on the line, element " + quote(el.name) +
                  " has " + std::to_string(t));
}

// ascii: one element instance per (non-blank) line.
void read_ascii(const Header& h, LineCursor& cur, std::size_t remaining, const std::string& name, Cloud& cloud) {
  const std::uint64_t nvert = h.vertex().count;
  if (nvert > remaining / 2 + 1)
    fail_line(name, h.vertex().header_line,
              "wrong counts: " + std::to_string(nvert) + " vertices cannot fit in the " + std::to_string(remaining) +
                  " bytes after the header");
  cloud.xyz.resize(3 * nvert);
  std::string_view line;
  std::vector<std::string_view> tok;
  for (std::size_t e = 0; e < h.elements.size(); ++e) {
    const Element& el = h.elements[e];
    if (el.props.empty()) continue;
    for (std::uint64_t i = 0; i < el.count; ++i) {
      do {
        if (!cur.next(line))
          fail_line(name, cur.line_no,
                    "truncated data: file ends at element " + quote(el.name) + " " + std::to_string(i) + " of " +
                        std::to_string(el.count));
        split_blanks(line, tok);
      } while (tok.empty());
      read_ascii_instance(h, e, i, tok, cur.line_no, name, cloud);
    }
  }
  while (cur.next(line))
    if (!trim(line).empty()) fail_line(name, cur.line_no, "wrong counts: data after the last element");
}

}  // namespace

Cloud parse_ply(std::string_view data, const std::string& name) {
  LineCursor cur{data};
  std::string_view line;
  if (!cur.next(line) || trim(line) != "ply") fail_line(name, 1, "bad header: file does not start with 'ply'");
  Header h = read_header(cur, name);
  find_vertex(h, name);
  Cloud cloud;
  cloud.has_z = h.axis_prop[2] >= 0;
  cloud.format = "ply " + h.format;
  if (h.format == "binary_little_endian") read_binary(h, data, cur.pos, name, cloud);
  else
    read_ascii(h, cur, data.size() - cur.pos, name, cloud);
  return count_nonfinite(cloud);
}

}  // namespace hg::outline_io
