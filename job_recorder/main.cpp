#include <exception>

#include "job_recorder/job_recorder.hpp"
#include "runtime/log.hpp"

int main(int argc, char** argv) {
  hg::runtime::Node node(hg::job_recorder::process_info(), argc, argv);
  try {
    auto recorder = hg::job_recorder::attach(node);
    const int rc = node.run();
    recorder->stop(hg::runtime::now_utime());  // open jobs: interrupted, with their last known state
    return rc;
  } catch (const std::exception& e) {
    hg::runtime::logf(hg::runtime::Level::Error, "%s", e.what());
    return 2;
  }
}
