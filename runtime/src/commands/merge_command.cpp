// plugslam merge S1 S2 ... -o OUT: saved sessions joined into one by place recognition.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <iostream>

#include "cli.h"
#include "commands/commands.h"
#include "plugin_manager.h"
#include "session/merge.h"

namespace plugslam::runtime {

void addMergeCommand(CLI::App& root, int& exit_code) {
  auto* cmd = root.add_subcommand(
      "merge", "Join saved sessions into one where place recognition links them");
  cmd->footer(
      "The sessions' graphs are restored side by side with no known relative pose; place\n"
      "recognition (a loop detector that does not use the estimate, e.g. laser2d.PlaceRecognizer\n"
      "in the first session's config) proposes links, the validators and loop filters check them,\n"
      "and the joined graph is optimized as one. OUT gets the merged session (OUT/session), the\n"
      "config's outputs over the merged maps (map, graph, trajectory.tum), one trajectory per\n"
      "input in the merged frame (trajectory_K.tum, K = the session's place on the command line)\n"
      "and merge.json. A session that shares no place with the first is reported and left out;\n"
      "exit 1 when none joins.");
  static MergeOptions o;
  static std::string out_dir = "merged";
  cmd->add_option("SESSIONS", o.sessions, "session folders (the first one's config is used)")
      ->required()
      ->expected(2, -1);
  cmd->add_option("-o,--output", out_dir, "output folder (created if missing)")
      ->capture_default_str();
  cmd->add_option("--set", o.sets, "override a parameter of that config: PATH=VALUE (repeatable)");
  cmd->callback([&exit_code] {
    o.out_dir = out_dir;
    PluginManager plugins;
    const MergeReport r = mergeSessions(o, plugins);
    size_t joined = 0;
    for (const auto& in : r.inputs) {
      joined += in.joined;
      std::cout << fmt::format("{}: {} maps, {}{}\n", in.dir, in.maps,
                               in.joined ? fmt::format("merged ({} links)", in.links)
                                         : "not merged: shares no place found with the others",
                               in.joined ? ", trajectory " + in.trajectory_file : "");
    }
    if (joined < 2) {
      std::cout << "nothing merged: no session shares a place found with the first\n";
      exit_code = kRuntimeFailure;
      return;
    }
    std::cout << fmt::format(
        "merged {} of {} sessions: {} maps, {} edges, {} links across sessions, {:.1f} s; "
        "outputs in {}, session in {}/session\n",
        joined, r.inputs.size(), r.maps, r.edges, r.links, r.seconds, out_dir, out_dir);
    exit_code = kOk;
  });
}

}  // namespace plugslam::runtime
