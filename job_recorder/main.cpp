#include "job_recorder/job_recorder.hpp"
#include "runtime/process.hpp"

int main(int argc, char** argv) {
  return hg::runtime::run_process(hg::job_recorder::process_info(), argc, argv, hg::job_recorder::attach);
}
