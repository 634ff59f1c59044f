#include "outline_service/outline_service.hpp"

int main(int argc, char** argv) {
  hg::runtime::Node node(hg::outline_service::process_info(), argc, argv);
  try {
    hg::outline_service::OutlineService service(node);
    return node.run();
  } catch (const hg::runtime::ConfigError& e) {
    hg::runtime::logf(hg::runtime::Level::Error, "%s", e.what());
    return 2;
  }
}
