// The planner's configuration (PlannerConfig) from its parameters and the cell file.
#pragma once

#include "cell/cell_params.hpp"
#include "path_planner/params.hpp"
#include "path_planner/pipeline.hpp"

namespace hg::path_planner {

// Reads the cell file (parameter cell) and the parameters. Throws runtime::ConfigError naming the parameter
// (and where it came from) when a value is unusable or contradicts the cell, or the cell file and its key.
PlannerConfig config_from(const ParamLookup& lookup);
PlannerConfig config_from(const ParamLookup& lookup, const cell::LoadedCell& cell);

}  // namespace hg::path_planner
