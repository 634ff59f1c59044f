#include "outline_service/outline_service.hpp"

int main(int argc, char** argv) {
  hg::runtime::Node node(hg::outline_service::process_info(), argc, argv);
  hg::outline_service::attach(node);
  return node.run();
}
