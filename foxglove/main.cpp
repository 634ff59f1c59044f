#include "foxglove/live.hpp"
#include "runtime/process.hpp"

int main(int argc, char** argv) {
  return hg::runtime::run_process(hg::foxglove::process_info(), argc, argv, hg::foxglove::attach);
}
