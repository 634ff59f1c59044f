// --version for every hullgrind program (the project's version from CMakeLists.txt's project()).
#pragma once

namespace hg::runtime {

const char* version();

// For programs with a command line of their own: when argv holds --version, prints "NAME VERSION" on
// standard output and returns true (main then returns 0, having touched nothing).
bool answer_version(int argc, const char* const* argv, const char* name);

}  // namespace hg::runtime
