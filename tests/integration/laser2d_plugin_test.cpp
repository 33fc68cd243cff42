// The laser2d plugin as the host sees it: loaded by the plugin manager, its types created by
// name and wired into a MultiTracker2D through the SDK interfaces only, its value type
// registered, and everything removed again on unload.
#include <gtest/gtest.h>

#include "plugin_manager.h"
#include "plugslam/multi_tracker.h"
#include "plugslam/pipeline.h"
#include "plugslam/preprocessor.h"
#include "plugslam/sink.h"
#include "plugslam/value_types.h"
#include "synthetic.h"
#include "test_paths.h"

namespace plugslam::laser2d {
namespace {

template <class I>
std::shared_ptr<I> make(const std::string& type) {
  auto object = std::dynamic_pointer_cast<I>(Registry::instance().create(type));
  EXPECT_TRUE(object) << type << " is not a " << I::kKind;
  if (object) object->configure();
  return object;
}

TEST(Laser2dPlugin, LoadsRegistersAndTracks) {
  runtime::PluginManager pm;
  pm.addSearchDir(plugslam::testing::buildDir() + "/plugins");
  const auto& info = pm.load("laser2d");
  EXPECT_EQ(info.name, "laser2d");
  for (const char* t :
       {"laser2d.ScanPreprocessor", "laser2d.PointToLineSlice", "laser2d.PointToPointSlice",
        "laser2d.PointMapSlice", "laser2d.OccupancyMapWriter"})
    EXPECT_TRUE(Registry::instance().find(t)) << t;
  EXPECT_TRUE(ValueTypes::instance().findByTag("laser2d.PointCloud2D"));

  {
    auto pre = make<PreProcessor>("laser2d.ScanPreprocessor");
    MultiTracker<Space2D> tracker;
    auto aligner = std::make_shared<MultiAligner<Space2D>>();
    aligner->slices.assign(make<AlignerSlice<Space2D>>("laser2d.PointToLineSlice"));
    tracker.aligner.assign(aligner);
    tracker.slices.assign(make<TrackerSlice<Space2D>>("laser2d.PointMapSlice"));
    tracker.configure();
    Pipeline pipeline;  // places the local maps and composes the world pose
    pipeline.tracker.assign(std::shared_ptr<Tracker>(std::shared_ptr<Tracker>(), &tracker));
    ASSERT_TRUE(pre);
    const auto world = test::room(8, 6);
    test::ScanSpec spec;
    for (int k = 0; k < 10; ++k) {
      Frame frame;
      frame.seq = k;
      frame.stamp = k;
      frame.raw.set("front_laser", test::castScan(world, se2(2 + 0.1 * k, 2, 0.02 * k), spec));
      ASSERT_TRUE(pre->process(frame));
      // The measurement is the plugin's value type, known to the SDK by its tag.
      EXPECT_EQ(frame.measurement.at("front").tag(), "laser2d.PointCloud2D");
      pipeline.process(frame);
      const Eigen::Vector3d v = toVector(Space2D::from3D(frame.estimate.world));
      EXPECT_NEAR(v.x(), 0.1 * k, 1e-3);
      EXPECT_NEAR(v.y(), 0.0, 1e-3);
      EXPECT_NEAR(v.z(), 0.02 * k, 1e-3);
    }
    EXPECT_EQ(tracker.stats().failed, 0u);
  }
  pm.unload("laser2d");
  EXPECT_FALSE(Registry::instance().find("laser2d.PointToLineSlice"));
  EXPECT_FALSE(ValueTypes::instance().findByTag("laser2d.PointCloud2D"));
}

}  // namespace
}  // namespace plugslam::laser2d
