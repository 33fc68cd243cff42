// plugslam render RUN_DIR: PNG, SVG or PDF pictures of what a run wrote (map, trajectories, loop
// closures, error plots), for people who would rather look than read.
#include <CLI/CLI.hpp>
#include <iostream>

#include "cli.h"
#include "commands/commands.h"
#include "plugslam/errors.h"
#include "render/run_pictures.h"

namespace plugslam::runtime {

void addRenderCommand(CLI::App& root, int& exit_code) {
  auto* cmd = root.add_subcommand(
      "render", "Draw a run's output folder: map, paths, loops, errors (PNG, SVG, PDF)");
  cmd->footer(
      "Writes render_map.EXT (map, estimated trajectory, reference aligned onto it, loop\n"
      "closures) and, with a reference, render_errors.EXT (ATE per pose over time and distance,\n"
      "RPE over distance), one file per --format (png, svg, pdf; default png,svg).");
  static std::string dir, out, align = "auto";
  static render::RenderOptions o;
  cmd->add_option("RUN_DIR", dir, "folder written by `plugslam run -o RUN_DIR`")->required();
  cmd->add_option("-o,--output", out, "where the pictures go (default: RUN_DIR)");
  cmd->add_option("--trajectory", o.estimate_file,
                  "estimated trajectory (default: RUN_DIR/trajectory.tum)");
  cmd->add_option("--reference", o.reference_file,
                  "reference or ground truth (default: RUN_DIR/reference.tum or ground_truth.tum)");
  cmd->add_option("--align", align,
                  "alignment of the reference onto the estimate: auto (se2 for planar runs, else "
                  "se3), none, se2, se3, sim3")
      ->check(CLI::IsMember({"auto", "none", "se2", "se3", "sim3"}))
      ->capture_default_str();
  cmd->add_option("--width", o.width, "picture width [px]")
      ->check(CLI::Range(300, 8000))
      ->capture_default_str();
  cmd->add_option("--format", o.formats, "picture formats, comma-separated: png, svg, pdf")
      ->delimiter(',')
      ->check(CLI::IsMember({"png", "svg", "pdf"}))
      ->capture_default_str();
  cmd->add_option("--rpe-delta", o.rpe_delta, "RPE segment length [m]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->callback([&exit_code] {
    if (align != "auto") o.alignment = parseAlignment(align);
    for (const auto& f : render::renderRun(dir, out.empty() ? dir : out, o))
      std::cout << "wrote " << f << "\n";
    exit_code = kOk;
  });
}

}  // namespace plugslam::runtime
