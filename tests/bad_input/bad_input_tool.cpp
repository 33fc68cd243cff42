// Reads one pose graph or archive the way `plugslam optimize` and the session loader do, for the
// bad-input corpus: exits 2 on bad input (InputError, message on stderr), 1 on other failures,
// 0 when the input was accepted (a summary on stdout, warnings included).
//   bad_input_tool graph FILE [--project-information]
//   bad_input_tool archive FILE
#include <cstdio>
#include <exception>
#include <string>

#include "plugslam/archive.h"
#include "plugslam/errors.h"
#include "plugslam/property_container.h"
#include "plugslam/solver/optimize_graph_file.h"

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: bad_input_tool graph FILE [--project-information]\n"
               "       bad_input_tool archive FILE\n");
  return 2;
}

int graph(const std::string& file, bool project) {
  plugslam::OptimizeOptions options;
  options.input = file;
  options.max_iterations = 20;
  options.init = plugslam::InitMethod::kBest;
  options.project_information = project;
  const plugslam::OptimizeReport report = plugslam::optimizeGraphFile(options);
  std::printf("%s: %s %dD, %zu vertices, %zu edges, projected %zu, chi2 %g -> %g\n", file.c_str(),
              report.file.format.c_str(), report.file.dimension, report.file.vertices,
              report.file.edges, report.file.projected_information, report.initial_chi2,
              report.final_chi2);
  if (report.file.skipped_records > 0)
    std::printf("warning: skipped %zu record(s) of types this reader does not know\n",
                report.file.skipped_records);
  return 0;
}

int archive(const std::string& file) {
  plugslam::PropertyContainer container;
  plugslam::loadArchiveFile(file, [&](plugslam::InArchive& ar) { load(ar, container); });
  std::printf("%s: %zu properties\n", file.c_str(), container.size());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  const std::string command = argv[1];
  const std::string file = argv[2];
  try {
    if (command == "graph") {
      const bool project = argc > 3 && std::string(argv[3]) == "--project-information";
      return graph(file, project);
    }
    if (command == "archive") return archive(file);
    return usage();
  } catch (const plugslam::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "failure: %s\n", e.what());
    return 1;
  }
}
