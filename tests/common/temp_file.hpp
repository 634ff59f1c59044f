// A YAML file with the given content under /tmp for a test to read (config files); the test unlinks it.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

namespace hg::test {

inline std::string temp_yaml(const std::string& content) {
  char name[] = "/tmp/hg-test-XXXXXX.yaml";
  const int fd = mkstemps(name, 5);
  EXPECT_GE(fd, 0);
  EXPECT_EQ(write(fd, content.data(), content.size()), ssize_t(content.size()));
  close(fd);
  return name;
}

}  // namespace hg::test
