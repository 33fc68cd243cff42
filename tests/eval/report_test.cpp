#include "plugslam/eval/report.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

namespace plugslam {
namespace {

Trajectory line(double scale) {
  Trajectory t;
  for (int i = 0; i < 5; ++i) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation() = Eigen::Vector3d(scale * i, 0.5 * i * i, 0.0);
    t.push_back(i, p);
  }
  return t;
}

TEST(ReportTest, AteJsonParsesAndCarriesTheNumbers) {
  const AteResult r = computeAte(line(1.0), line(1.0), {Alignment::None, {}});
  // JSON is a subset of YAML, so yaml-cpp checks that the text is well formed.
  const YAML::Node n = YAML::Load(toJson(r));
  EXPECT_EQ(n["metric"].as<std::string>(), "ate");
  EXPECT_EQ(n["alignment"].as<std::string>(), "none");
  EXPECT_EQ(n["translation_m"]["count"].as<int>(), 5);
  EXPECT_DOUBLE_EQ(n["translation_m"]["rmse"].as<double>(), 0.0);
  const std::string md = toMarkdown(r);
  EXPECT_NE(md.find("| rmse | 0.000000 | 0.000000 |"), std::string::npos) << md;
}

TEST(ReportTest, RpeRelationsAndCrispnessRender) {
  RpeOptions o;
  const RpeResult rpe = computeRpe(line(1.0), line(1.5), o);
  const YAML::Node n = YAML::Load(toJson(rpe));
  EXPECT_EQ(n["unit"].as<std::string>(), "frames");
  EXPECT_EQ(n["pairs"].as<int>(), 4);
  EXPECT_NEAR(n["translation_m"]["mean"].as<double>(), 0.5, 1e-9);
  EXPECT_NEAR(n["translation_percent"]["mean"].as<double>(), rpe.translation_percent.mean, 1e-6);  // 9 digits
  EXPECT_NEAR(n["length_m"]["mean"].as<double>(), rpe.length_m.mean, 1e-7);
  EXPECT_NE(toMarkdown(rpe).find("% of the segment's path length"), std::string::npos);

  const RelationResult rel = evaluateRelations(line(1.5), relationsFromTrajectory(line(1.0), 0));
  const YAML::Node m = YAML::Load(toJson(rel));
  EXPECT_EQ(m["used"].as<int>(), 4);
  EXPECT_NEAR(m["translation_m"]["mean"].as<double>(), rel.translation.mean, 1e-9);
  EXPECT_NE(toMarkdown(rel).find("rotation (deg)"), std::string::npos);

  CrispnessResult c;
  c.mean = 0.0174;
  c.points = 10;
  c.matched_points = 7;
  const YAML::Node k = YAML::Load(toJson(c));
  EXPECT_DOUBLE_EQ(k["mean_m"].as<double>(), 0.0174);
  EXPECT_EQ(k["matched_points"].as<int>(), 7);
  EXPECT_DOUBLE_EQ(k["coverage"].as<double>(), 0.7);
  EXPECT_NE(toMarkdown(c).find("| mean nearest distance (m) | 0.017400 |"), std::string::npos);
  EXPECT_NE(toMarkdown(c).find("| coverage | 0.700000 |"), std::string::npos);
}

}  // namespace
}  // namespace plugslam
