#include "path_planner/outline_input.hpp"

namespace hg::path_planner {

namespace {

Vec3 vec3(const std::array<double, 3>& a) { return Vec3(a[0], a[1], a[2]); }

}  // namespace

OutlineInput outline_input(const outline_io::OutlineFile& file, const Plane& default_plane) {
  OutlineInput in;
  in.frame = file.frame;
  in.point_spacing = file.spacing;
  in.plane = default_plane;
  if (file.plane) {
    const outline_io::Plane& p = *file.plane;
    in.plane = {vec3(p.origin), vec3(p.u), vec3(p.v), vec3(p.normal)};
    in.plane_given = true;
  }
  for (const outline_io::OutlineLoop& l : file.loops) {
    Loop loop;
    loop.hole = l.hole;
    loop.points.reserve(l.points.size());
    for (const auto& p : l.points) loop.points.emplace_back(p.x, p.y);
    in.loops.push_back(std::move(loop));
  }
  return in;
}

OutlineInput read_outline_file(const std::string& path, const Plane& default_plane) {
  return outline_input(outline_io::read_outline_file(path), default_plane);
}

OutlineInput read_outline_json(const std::string& text, const Plane& default_plane, const std::string& name) {
  return outline_input(outline_io::parse_outline_file(text, name), default_plane);
}

}  // namespace hg::path_planner
