#include "dds_gateway/dds_gateway.hpp"
#include "runtime/process.hpp"

int main(int argc, char** argv) {
  return hg::runtime::run_process(hg::dds_gateway::process_info(), argc, argv, hg::dds_gateway::attach);
}
