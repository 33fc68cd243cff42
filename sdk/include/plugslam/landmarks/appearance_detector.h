#pragma once
// Appearance-based loop detection for the landmark cue, with no vocabulary file: the binary
// descriptors of every closed local map go into a Hamming search tree built online (after HBST,
// Schlegel and Grisetti 2018), and a new map's descriptors vote for the older maps they match,
// each vote weighing 1 / the maps that descriptor matched (a repeated texture's corners weigh
// little).
// It proposes maps that look alike; a geometric validator decides whether they are the same place.
#include <memory>
#include <string>

#include "plugslam/loop_closure.h"

namespace plugslam {
inline namespace abi_v1 {

/// Proposes the older local maps whose landmark descriptors match the query's most
/// ("sdk.AppearanceDetector"); it finds revisits whatever the drift of the estimate, and places
/// of other graph components (its candidates are `global`: place recognition).
class AppearanceDetector : public LoopDetector {
 public:
  AppearanceDetector();
  ~AppearanceDetector() override;
  Param<std::string> scene{this, "scene", "landmarks", "",
                           "scene entry of the landmark cue (LandmarkMap)"};
  Param<int> max_distance{this, "max_distance", 50, "bits",
                          "Hamming distance of a descriptor match (50 of ORB's 256 bits: the "
                          "bound below which two ORB descriptors are the same corner)",
                          Range{0, 4096}};
  Param<int> min_observations{this, "min_observations", 2, "",
                              "only landmarks matched in this many frames are indexed and "
                              "queried (one-frame landmarks are often spurious)",
                              Range{1, 1000000}};
  Param<int> min_matches{this, "min_matches", 30, "",
                         "query landmarks that must match a candidate (fewer do not make a "
                         "pose a geometric check can trust)",
                         Range{1, 1000000}};
  Param<double> min_ratio{this, "min_ratio", 0.05, "",
                          "fraction of the query's landmarks that must match a candidate",
                          Range{0, 1}};
  Param<double> min_travel{this, "min_travel", 10.0, "m",
                           "ignore maps fewer metres back along the path (they are neighbours, "
                           "which the tracker already joins); not applied across components",
                           Range{0, 1e9}};
  Param<double> place_margin{
      this, "place_margin", 0.5, "",
      "in another graph component (place recognition), the best-voted map must hold this "
      "fraction more vote weight than any of that component's maps `min_travel` or more of path "
      "from it: a place seen again, not a repeated texture",
      Range{0, 100}};
  Param<int> max_candidates{this, "max_candidates", 3, "", "best-voted candidates proposed",
                            Range{1, 1000}};
  Param<int> leaf_size{this, "leaf_size", 64, "",
                       "descriptors per tree leaf before it splits on its most balanced bit "
                       "(larger: more exact, slower)",
                       Range{2, 1000000}};
  Param<int> max_depth{this, "max_depth", 24, "", "tree depth limit", Range{1, 256}};

  void configure() override;
  /// Indexes every older map not indexed yet (also a restored session's), searches the index for
  /// `query`, then indexes `query`. Candidates are unmatched: validators find the pose.
  std::vector<LoopCandidate> detect(const GraphView& view, const LocalMap& query) override;

 private:
  struct Index;  // the Hamming tree (sdk/src/landmarks/appearance_detector.cpp)
  std::unique_ptr<Index> index_;
};

}  // namespace abi_v1
}  // namespace plugslam
