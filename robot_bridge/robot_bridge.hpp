// hg-robot-bridge: accepted jobs' grind paths (HG_GRIND_PATH) -> robot (sim or Universal Robots) ->
// HG_ROBOT_STATUS (100 Hz), HG_JOB_STATUS. See docs/robot_bridge.md.
#pragma once

#include <memory>

#include "cell/cell_params.hpp"
#include "robot_bridge/bridge.hpp"
#include "runtime/node.hpp"

namespace hg::robot_bridge {

runtime::ProcessInfo process_info();

// The running process: the bridge plus its wiring. Lives as long as the node runs.
class Process;
struct ProcessDeleter {
  void operator()(Process* p) const;
};
using ProcessHandle = std::unique_ptr<Process, ProcessDeleter>;

// Wires the process's subscriptions and timers onto a node. Throws std::exception on a bad configuration.
ProcessHandle attach(runtime::Node& node);

// The cell's limits (from the cell file named by --cell) and the URScript options (accel within the cell's
// max-accel) from the bridge's parameters. Throw runtime::ConfigError naming the key (and the cell file).
Limits limits_from(const runtime::Params& params);
ScriptOptions script_from(const runtime::Params& params, const cell::LoadedCell& cell);

// hg-robot-export: writes the URScript of a path file and returns the exit code (0 when the path passes the
// configured checks, 1 otherwise; the script is written only when it passes).
int export_script(const runtime::Params& params, const std::string& path_file, const std::string& out_file);

}  // namespace hg::robot_bridge
