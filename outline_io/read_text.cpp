// .xyz / .txt / .csv: one point per line, "x y [z]" separated by blanks and/or commas; '#' starts a
// comment; one header line is skipped only if it comes first and none of its fields is a number.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "outline_io/read_common.hpp"

namespace hg::outline_io {

using namespace detail;

namespace {

// Fields separated by blanks and/or single commas; "1,,2" or a dangling comma is an empty field.
// Returns false (and the column of the problem) on an empty field.
bool split_fields(std::string_view line, std::vector<std::string_view>& out, std::size_t& bad_col) {
  out.clear();
  std::size_t i = 0, n = line.size();
  bool need_field = false;  // a comma was seen and no field since
  while (true) {
    while (i < n && is_space(line[i])) ++i;
    if (i >= n) {
      if (need_field) {
        bad_col = out.size() + 1;
        return false;
      }
      return true;
    }
    if (line[i] == ',') {
      if (out.empty() || need_field) {
        bad_col = out.size() + 1;
        return false;
      }
      need_field = true;
      ++i;
      continue;
    }
    std::size_t s = i;
    while (i < n && !is_space(line[i]) && line[i] != ',') ++i;
    out.push_back(line.substr(s, i - s));
    need_field = false;
  }
}

bool has_letter(std::string_view s) {
  return std::any_of(s.begin(), s.end(), [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); });
}

}  // namespace

Cloud parse_text_cloud(std::string_view data, const std::string& name) {
  Cloud cloud;
  cloud.format = "xyz";
  if (data.size() >= 3 && data.substr(0, 3) == "\xEF\xBB\xBF") data.remove_prefix(3);  // UTF-8 BOM
  // One pass to count lines gives the capacity without guessing from the file size.
  cloud.xyz.reserve(3 * (static_cast<std::size_t>(std::count(data.begin(), data.end(), '\n')) + 1));

  LineCursor cur{data};
  std::string_view line;
  std::vector<std::string_view> fields;
  std::size_t columns = 0;  // fixed by the first data line
  bool header_seen = false;
  while (cur.next(line)) {
    if (auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    std::size_t bad_col = 0;
    if (!split_fields(line, fields, bad_col))
      fail_line(name, cur.line_no, "empty field in column " + std::to_string(bad_col));
    if (fields.empty()) continue;

    if (columns == 0 && !header_seen) {
      // Header: only if no field parses as a number (nan/inf count as numbers) and some field has a letter.
      bool any_numeric = false, any_letter = false;
      for (auto f : fields) {
        double v;
        if (parse_number(f, v) != Num::Bad) any_numeric = true;
        if (has_letter(f)) any_letter = true;
      }
      if (!any_numeric && any_letter) {
        header_seen = true;
        continue;
      }
    }
    if (columns == 0) {
      if (fields.size() < 2)
        fail_line(name, cur.line_no, "expected x y [z], found " + std::to_string(fields.size()) + " value");
      columns = fields.size();
      cloud.has_z = columns >= 3;
    } else if (fields.size() != columns) {
      fail_line(name, cur.line_no,
                "wrong number of values: " + std::to_string(fields.size()) + " (earlier lines have " +
                    std::to_string(columns) + ")");
    }
    double v[3] = {0, 0, 0};
    const int used = cloud.has_z ? 3 : 2;
    for (int k = 0; k < used; ++k) {
      switch (parse_number(fields[k], v[k])) {
        case Num::Ok:
        case Num::NonFinite: break;  // a NaN/Inf point is kept and counted
        case Num::Bad:
          fail_line(name, cur.line_no, std::string("bad number ") + quote(fields[k]) + " for " + axis_name(k));
        case Num::Range:
          fail_line(name, cur.line_no, std::string("number out of range ") + quote(fields[k]) + " for " + axis_name(k));
      }
    }
    cloud.xyz.insert(cloud.xyz.end(), v, v + 3);
  }
  if (cloud.xyz.empty()) fail_file(name, "no points in file");
  return count_nonfinite(cloud);
}

const char* format_name(Format f) {
  switch (f) {
    case Format::Text: return "xyz";
    case Format::Pcd: return "pcd";
    case Format::Ply: return "ply";
  }
  return "?";
}

Format format_from_path(const std::string& path) {
  auto dot = path.find_last_of('.');
  auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
    throw ReadError(path + ": unsupported format: no file extension (expected .xyz .txt .csv .pcd .ply)");
  std::string ext = path.substr(dot + 1);
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == "xyz" || ext == "txt" || ext == "csv") return Format::Text;
  if (ext == "pcd") return Format::Pcd;
  if (ext == "ply") return Format::Ply;
  throw ReadError(path + ": unsupported format '." + ext + "' (expected .xyz .txt .csv .pcd .ply)");
}

Cloud read_cloud_file(const std::string& path) {
  Format fmt = format_from_path(path);
  std::error_code ec;
  auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) throw ReadError(path + ": cannot open file: no such file");
  if (!std::filesystem::is_regular_file(status)) throw ReadError(path + ": cannot read: not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ReadError(path + ": cannot open file (permission?)");
  // Read to the end rather than trusting a size taken before: the file may change under us.
  std::string data;
  auto size = std::filesystem::file_size(path, ec);
  if (!ec) data.reserve(size);
  char buf[1 << 16];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) data.append(buf, static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw ReadError(path + ": read error");
  switch (fmt) {
    case Format::Text: return parse_text_cloud(data, path);
    case Format::Pcd: return parse_pcd(data, path);
    case Format::Ply: return parse_ply(data, path);
  }
  throw ReadError(path + ": unsupported format");
}

}  // namespace hg::outline_io
