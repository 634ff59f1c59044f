// The planner's edges, for the programs and tests that use them all: its parameters and configuration, the
// outline file and its frame, the path file, the messages. One header each; this one includes them.
#pragma once

#include "path_planner/config.hpp"
#include "path_planner/lcm.hpp"
#include "path_planner/outline_frame.hpp"
#include "path_planner/outline_input.hpp"
#include "path_planner/params.hpp"
#include "path_planner/path_json.hpp"
