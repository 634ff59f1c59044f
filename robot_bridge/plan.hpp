// The plan a job holds in the robot bridge (grind_path_t with its coverage): what the approval may take out
// of it (excluded loops), whether the cell's auto policy may approve it, and what a run of it leaves unground.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hullgrind/edge_stretch_t.hpp"
#include "hullgrind/grind_path_t.hpp"

namespace hg::robot_bridge {

// True when the plan reaches every edge of the part: no unreached stretch and every loop of its coverage
// planned (the only plan `approval: auto` may approve).
bool fully_reached(const hullgrind::grind_path_t& plan);

// Empty when every loop index names a loop of the plan (its coverage, or a waypoint's loop_index); else why not.
std::string check_exclusions(const hullgrind::grind_path_t& plan, const std::vector<std::int16_t>& excluded);

// The plan without the excluded loops: every waypoint of theirs (approach, lead-in, grind, lead-out, retract)
// and the air move into each removed, so the air moves at safe height join the neighbours. Coverage and unreached are
// kept (unground() tells the excluded loops apart).
hullgrind::grind_path_t without_loops(const hullgrind::grind_path_t& plan, const std::vector<std::int16_t>& excluded);

// Number of grind waypoints (KIND_GRIND) in a path.
int grind_waypoints(const hullgrind::grind_path_t& plan);

// Every stretch of edge a complete run of the plan leaves unground: the plan's unreached stretches of the loops
// not excluded (their own cause), and each excluded loop whole (CAUSE_EXCLUDED, the reason naming `actor`).
std::vector<hullgrind::edge_stretch_t> unground(const hullgrind::grind_path_t& plan,
                                                const std::vector<std::int16_t>& excluded, const std::string& actor);

// True when a stretch's cause is CAUSE_EXCLUDED.
bool is_excluded(const hullgrind::edge_stretch_t& s);

// One line listing stretches: "hole 2: 31.4 mm (too small: ...); outer loop 0: 3.2 mm at 120.0 mm (unreached: ...)".
std::string describe(const std::vector<hullgrind::edge_stretch_t>& stretches);

// "3, 5".
std::string loop_list(const std::vector<std::int16_t>& loops);

}  // namespace hg::robot_bridge
