#pragma once
// Reading a source's frames in the source tests. Header-only.
#include <gtest/gtest.h>

#include <cstdint>

#include "plugslam/frame.h"

namespace plugslam::testing {

/// Reads a configured source to its end into `f` (which keeps the last frame), expecting
/// strictly increasing stamps, and gives each frame to `each`; returns how many there were.
template <class Source, class Each>
int64_t readInOrder(Source& source, Frame& f, Each each) {
  int64_t frames = 0;
  double last = -1;
  while (source.next(f)) {
    EXPECT_GT(f.stamp, last);
    last = f.stamp;
    each(f);
    ++frames;
  }
  return frames;
}

}  // namespace plugslam::testing
