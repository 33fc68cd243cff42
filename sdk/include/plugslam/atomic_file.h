#pragma once
// Atomic file output: a crash or an exception never leaves a half-written target behind.
#include <functional>
#include <iosfwd>
#include <string>

namespace plugslam {
inline namespace abi_v1 {

/// Writes `path` atomically: `write` fills a new temp file `<path>.tmp-XXXXXX` in the same folder,
/// which is flushed, fsync'ed and renamed over `path` (then the folder is fsync'ed). If `write`
/// throws or any step fails, the temp file is removed and `path` keeps its old content. Throws
/// InputError when the file cannot be created or written (with the system's reason).
void writeFileAtomically(const std::string& path,
                         const std::function<void(std::ostream& out)>& write);

}  // namespace abi_v1
}  // namespace plugslam
