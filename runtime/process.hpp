// The one way a hullgrind process starts. Every main.cpp is one line:
//   int main(int argc, char** argv) { return hg::runtime::run_process(hg::x::process_info(), argc, argv,
//   hg::x::attach); }
// 1. builds the node from argv: --help / --version answer and exit 0; a bad command line or config file is
//    one line naming it and the key, exit 2;
// 2. attach(node) wires the process onto the node and returns what must live while the loop runs (or
//    nothing). A bad parameter value found by the process's own checks (ConfigError, std::invalid_argument:
//    a bad config, cell or input file) is one line on stderr naming the file and the key, exit 2; any other
//    failure to start is one line, exit 1. Either comes before LCM is opened or anything else is logged,
//    as long as attach checks its configuration before it subscribes (Node opens LCM on first use).
//    The failure contract of every program (docs/RUNNING.md): 0 success, 1 ran and failed, 2 bad command
//    line, config, cell or input file, with exactly one line on stderr;
// 3. runs the loop until SIGINT/SIGTERM; the attached object is destroyed after it (its destructor stops
//    the process's threads); returns the loop's exit code.
#pragma once

#include <functional>
#include <memory>
#include <type_traits>
#include <utility>

#include "runtime/node.hpp"

namespace hg::runtime {

int run_attached(ProcessInfo info, int argc, char** argv, const std::function<std::shared_ptr<void>(Node&)>& attach);

template <class Attach>
int run_process(ProcessInfo info, int argc, char** argv, Attach attach) {
  return run_attached(std::move(info), argc, argv, [&attach](Node& node) -> std::shared_ptr<void> {
    if constexpr (std::is_void_v<decltype(attach(node))>) {
      attach(node);
      return nullptr;
    } else {
      return std::shared_ptr<void>(attach(node));  // a unique_ptr keeps its deleter
    }
  });
}

// A parameter error's message as the process logs it: names the config file when the message does not.
std::string parameter_error_text(const Node& node, const std::string& what);

}  // namespace hg::runtime
