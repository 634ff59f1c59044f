// hullgrind outline I/O: point-cloud readers (.xyz/.txt/.csv, .pcd, .ply) and the best-fit plane.
// Every reader works on the whole file in memory, checks every count against the bytes present before
// allocating, and throws ReadError "FILE: line N: ..." (text) or "FILE: byte N: ..." (binary) on any defect.
// NaN and infinite values ("nan", "inf" in text) are no defect: the point is counted in Cloud::nonfinite.
#pragma once

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "outline_core/outline.hpp"

namespace hg::outline_io {

// The outline core's types, by the names the core gives them (this library is the layer above it).
using outline::AlphaMode;
using outline::Loop;
using outline::Mode;
using outline::Order;
using outline::OutlineError;
using outline::Result;
using outline::Vec2;

// A file that cannot be read: the message names the file and the line or byte offset, and what is wrong.
struct ReadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class Format { Text, Pcd, Ply };
const char* format_name(Format);

struct Cloud {
  std::vector<double> xyz;  // x, y, z interleaved, one triple per point in file order (z = 0 without z)
  bool has_z = false;       // the file gives a z coordinate
  std::string format;       // e.g. "xyz", "pcd binary_compressed", "ply binary_little_endian"
  // Points with a NaN or infinite coordinate (no-return pixels of depth cameras): kept in xyz as they are,
  // so indices stay positions in the file; to_plane and the core skip them.
  std::size_t nonfinite = 0;
  std::size_t size() const { return xyz.size() / 3; }
};

// Chooses the reader by extension (case-insensitive): .xyz .txt .csv, .pcd, .ply.
Format format_from_path(const std::string& path);  // throws ReadError for an unknown extension
Cloud read_cloud_file(const std::string& path);

// The readers proper; `name` is the file name used in messages. `data` is the whole file.
Cloud parse_text_cloud(std::string_view data, const std::string& name);
Cloud parse_pcd(std::string_view data, const std::string& name);
Cloud parse_ply(std::string_view data, const std::string& name);

// LZF (liblzf format, as used by PCD binary_compressed). Decodes exactly `out_size` bytes into `out`.
// `base_offset` is the offset of `in` in the file, for messages. Throws ReadError on any malformed input.
void lzf_decompress(std::string_view in, char* out, std::size_t out_size, const std::string& name,
                    std::size_t base_offset);

// Best-fit plane of a 3-D cloud. Right-handed (u, v, normal); u is the x axis projected onto the plane
// when the plane is not nearly perpendicular to it, so a plate seen from above keeps its orientation.
struct Plane {
  std::array<double, 3> origin{}, normal{}, u{}, v{};
};

struct PlanarPoints {
  std::vector<Vec2> points;  // in input order
  bool projected = false;    // true: 3-D input, points are (u, v) plane coordinates (a flat cloud: x, y)
  Plane plane;               // meaningful when projected
  double rms_distance = 0;   // RMS distance of the input points from the plane (0 when not projected)
  double max_distance = 0;
};

// Planar input (no z, or every finite z equal) keeps x, y as they are (with every z equal to z0, projected is
// true and the plane is z = z0 with the x, y axes: origin (0, 0, z0), u x, v y, normal z); otherwise least-squares
// plane (PCA) of the finite points, points given as plane coordinates about the centroid. A point with a non-finite
// coordinate becomes (NaN, NaN) (the core skips it). Throws ReadError (naming `name`) if the coordinates
// are too large for the least-squares sums, OutlineError if the finite points are collinear in space
// (the core's message for collinear 2-D input).
PlanarPoints to_plane(const Cloud& cloud, const std::string& name = "input");
std::array<double, 3> plane_to_3d(const Plane& plane, Vec2 p);

}  // namespace hg::outline_io
