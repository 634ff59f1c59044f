// hg-job-recorder: the job history (recorder.hpp) kept from the bus. See docs/job_recorder.md.
#pragma once

#include <memory>

#include "job_recorder/recorder.hpp"
#include "runtime/node.hpp"

namespace hg::job_recorder {

runtime::ProcessInfo process_info();

// Subscribes the job channels on the node and records into --dir. Throws std::exception when the directory
// cannot be made. Releasing the returned pointer stops the recorder (open jobs: interrupted).
std::shared_ptr<Recorder> attach(runtime::Node& node);

}  // namespace hg::job_recorder
