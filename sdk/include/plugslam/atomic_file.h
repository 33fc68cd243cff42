#pragma once
// Atomic file output: a crash or an exception never leaves a half-written target behind. The one
// writer of plugslam's result files (run.json, trajectories, graphs, maps, archives, images,
// summaries, configs); only a recording streamed during a run (MCAP) grows in place, since its
// format is made to be read up to where a crash cut it.
#include <functional>
#include <ostream>
#include <string>

namespace plugslam {
inline namespace abi_v1 {

/// Writes `path` atomically: `write` fills a new temp file `<path>.tmp-XXXXXX` in the same folder,
/// which is flushed, fsync'ed and renamed over `path` (then the folder is fsync'ed). If `write`
/// throws or any step fails, the temp file is removed and `path` keeps its old content. Throws
/// InputError when the file cannot be created or written (with the system's reason).
void writeFileAtomically(const std::string& path,
                         const std::function<void(std::ostream& out)>& write);

/// Writes `content` to `path` atomically, as above (inline: no symbol of its own in the ABI).
inline void writeFileAtomically(const std::string& path, const std::string& content) {
  writeFileAtomically(path, [&content](std::ostream& out) {
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
  });
}

}  // namespace abi_v1
}  // namespace plugslam
