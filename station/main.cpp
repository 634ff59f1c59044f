#include "runtime/process.hpp"
#include "station/station.hpp"

int main(int argc, char** argv) {
  return hg::runtime::run_process(hg::station::process_info(), argc, argv, hg::station::attach);
}
