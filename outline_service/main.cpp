#include "outline_service/outline_service.hpp"
#include "runtime/process.hpp"

int main(int argc, char** argv) {
  return hg::runtime::run_process(hg::outline_service::process_info(), argc, argv, hg::outline_service::attach);
}
