#include "runtime/process.hpp"

#include <cstdio>
#include <stdexcept>

namespace hg::runtime {

std::string parameter_error_text(const Node& node, const std::string& what) {
  if (what.find("config '") != std::string::npos || what.find("command line") != std::string::npos ||
      node.config().empty())
    return what;
  return what + " (command line or config '" + node.config().source() + "')";
}

int run_attached(ProcessInfo info, int argc, char** argv, const std::function<std::shared_ptr<void>(Node&)>& attach) {
  Node node(std::move(info), argc, argv);
  std::shared_ptr<void> process;
  try {
    process = attach(node);
  } catch (const ConfigError& e) {  // one line, as a bad command line (Node::parse): the failure contract
    std::fprintf(stderr, "%s: %s\n", node.name().c_str(), parameter_error_text(node, e.what()).c_str());
    return 2;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "%s: %s\n", node.name().c_str(), parameter_error_text(node, e.what()).c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: cannot start: %s\n", node.name().c_str(), e.what());
    return 1;
  }
  const int rc = node.run();
  process.reset();
  return rc;
}

}  // namespace hg::runtime
