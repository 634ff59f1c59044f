// The planner's parameters: one table for hg-path-planner, hg-plan and hg-overview (config/path_planner.yaml).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "runtime/node.hpp"
#include "runtime/params.hpp"

namespace hg::path_planner {

// Every planner parameter (hg-path-planner and hg-plan read the same keys, config/path_planner.yaml), with
// --cell: the camera-to-base calibration, table, workspace, speed and acceleration limits, tool and home come
// from the cell file (docs/cell.md); their old keys are declared as moved and refused naming the cell's key.
std::vector<runtime::Param> planner_params();
// The keys that moved into the cell file (part of planner_params()): refused naming the cell's key.
std::vector<runtime::Param> moved_planner_keys();

// Where parameter values come from (command line > config file > default, runtime::Params), for the
// process, hg-plan and hg-overview alike.
struct ParamLookup {
  std::shared_ptr<const runtime::Params> params;  // owned (lookup_from(cli, config)) or not (the others)
};
ParamLookup lookup_from(const runtime::Node& node);
ParamLookup lookup_from(const runtime::Params& params);  // params must outlive the lookup
// For tests: `cli` (name -> value, lists as "a,b,c") > `config` > the default of planner_params(), through
// the same runtime::Params (every program parses its command line with runtime::Params itself).
ParamLookup lookup_from(const std::map<std::string, std::string>& cli, const runtime::Config& config);
}  // namespace hg::path_planner
