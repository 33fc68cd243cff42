#include "cli.h"

#include <cstdio>

namespace plugslam::runtime {
int runCli(int, char**) {
  std::puts("plugslam (skeleton)");
  return kOk;
}
}  // namespace plugslam::runtime
