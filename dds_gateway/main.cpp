#include "dds_gateway/dds_gateway.hpp"

int main(int argc, char** argv) {
  hg::runtime::Node node(hg::dds_gateway::process_info(), argc, argv);
  hg::dds_gateway::attach(node);
  return node.run();
}
