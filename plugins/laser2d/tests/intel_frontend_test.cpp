// Integration: the laser2d front-end on the real intel log (GMapping-corrected poses as the
// reference). Thresholds fail when the aligner breaks; they are not the targets.
#include <gtest/gtest.h>

#include <filesystem>

#include "intel_run.h"
#include "test_paths.h"

namespace plugslam::laser2d {
namespace {

std::string intelLog() {
  return plugslam::testing::dataDir() + "/laser2d/intel-gfs-corrected/intel-corrected.log.gz";
}

TEST(IntelFrontend, LocalAccuracyAgainstTheCorrectedPoses) {
  if (!std::filesystem::exists(intelLog())) GTEST_SKIP() << "no intel log at " << intelLog();
  for (const char* association : {"kdtree", "projective"}) {
    test::FrontendOptions options;
    options.association = association;
    const auto run = test::runFrontend(intelLog(), options);
    ASSERT_EQ(run.scans, 910u);
    const auto rpe = test::relativeError(run, 1.0);
    std::printf("%s: %.0f scans/s, RPE 1 m: %.4f m, %.3f deg (mean), aligned %zu/%zu\n",
                association, run.scans_per_second, rpe.translation.mean, rpe.rotation_deg.mean,
                run.aligned, run.scans);
    EXPECT_GT(run.aligned, run.scans * 9 / 10) << association;
    EXPECT_LT(rpe.translation.mean, 0.05) << association;
    EXPECT_LT(rpe.rotation_deg.mean, 2.0) << association;
  }
}

}  // namespace
}  // namespace plugslam::laser2d
