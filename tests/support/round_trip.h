#pragma once
// A value saved to an archive and loaded back: how the tests of a type's save and load check
// that nothing is lost.
#include <sstream>

#include "plugslam/archive.h"

namespace plugslam::testing {

/// `value` written to an archive of `format` and read back (save and load found by ADL).
template <class T>
T roundTrip(ArchiveFormat format, const T& value) {
  std::stringstream io;
  {
    auto out = makeOutArchive(io, format);
    save(*out, value);
    out->finish();
  }
  auto in = makeInArchive(io, format);
  T back{};
  load(*in, back);
  return back;
}

}  // namespace plugslam::testing
