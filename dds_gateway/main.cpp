#include "dds_gateway/dds_gateway.hpp"

int main(int argc, char** argv) {
  hg::runtime::Node node(hg::dds_gateway::process_info(), argc, argv);
  std::unique_ptr<hg::dds_gateway::Gateway> gateway = hg::dds_gateway::attach(node);
  if (!gateway) return 1;  // the reason is logged
  return node.run();
}
