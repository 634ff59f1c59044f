// The outline service's options at their declared defaults (no cell file rules), for the
// planner's tests that outline rendered frames as the pipeline does.
#pragma once

#include <string>

#include "outline_service/outline_service.hpp"

namespace hg::path_planner::test {

inline hg::outline_service::ServiceOptions service_options() {
  hg::outline_service::ServiceOptions o;
  for (const hg::runtime::Param& p : hg::outline_service::process_info().params) {
    if (p.name == "mode") o.mode = hg::outline::parse_mode(p.default_value);
    if (p.name == "order") o.order = hg::outline::parse_order(p.default_value);
    if (p.name == "alpha-radius") o.alpha_radius = std::stod(p.default_value);
    if (p.name == "auto-factor") o.auto_factor = std::stod(p.default_value);
    if (p.name == "alpha-mode") o.alpha_mode = hg::outline::parse_alpha_mode(p.default_value);
    if (p.name == "min-hole-spacings") o.min_hole_spacings = std::stod(p.default_value);
  }
  return o;
}

}  // namespace hg::path_planner::test
