// The pipeline's per-frame record keeps a bounded number of records in memory and gives every
// record back, in order, however many moved to its temporary file.
#include "pose_log.h"

#include <gtest/gtest.h>

#include <vector>

namespace {
using plugslam::detail::PoseLog;

PoseLog::Entry entry(int i) {
  PoseLog::Entry e;
  e.stamp = 0.1 * i;
  e.key = i / 3;
  e.pose = Eigen::Translation3d(i, -2.0 * i, 0.5) *
           Eigen::AngleAxisd(0.3 * i, Eigen::Vector3d(1, 2, 3).normalized());
  return e;
}

std::vector<PoseLog::Entry> all(const PoseLog& log) {
  std::vector<PoseLog::Entry> out;
  log.forEach([&](const PoseLog::Entry& e) { out.push_back(e); });
  return out;
}

void expectSame(const std::vector<PoseLog::Entry>& got, int n) {
  ASSERT_EQ(got.size(), static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    SCOPED_TRACE(i);
    const PoseLog::Entry want = entry(i);
    EXPECT_DOUBLE_EQ(got[i].stamp, want.stamp);
    EXPECT_EQ(got[i].key, want.key);
    EXPECT_TRUE(got[i].pose.isApprox(want.pose, 0.0));  // bit for bit
  }
}

TEST(PoseLog, KeepsAtMostOneChunkInMemoryAndReturnsEveryRecordInOrder) {
  PoseLog log(4);
  for (int i = 0; i < 10; ++i) log.push_back(entry(i));
  EXPECT_EQ(log.size(), 10u);
  EXPECT_EQ(log.inMemory(), 2u);  // 8 records went to the file
  expectSame(all(log), 10);
}

TEST(PoseLog, AppendsAfterBeingRead) {
  PoseLog log(3);
  for (int i = 0; i < 7; ++i) log.push_back(entry(i));
  expectSame(all(log), 7);
  for (int i = 7; i < 20; ++i) log.push_back(entry(i));
  EXPECT_LT(log.inMemory(), 3u);
  expectSame(all(log), 20);
  expectSame(all(log), 20);  // reading twice gives the same
}

// The chunk is what a soak sees grow before the first spill: it must stay small next to a
// process's ~20 MiB (two logs of 16384 records were +19 % of a localization run).
TEST(PoseLog, DefaultChunkKeepsLittleInMemory) {
  EXPECT_LE(PoseLog::kDefaultChunk * 112, 128u * 1024);  // records of 112 bytes on disk
  PoseLog log;
  for (int i = 0; i < 5000; ++i) log.push_back(entry(i));
  EXPECT_LT(log.inMemory(), PoseLog::kDefaultChunk);
  expectSame(all(log), 5000);
}

TEST(PoseLog, EmptyAndSmallLogsStayInMemory) {
  PoseLog log;
  EXPECT_TRUE(log.empty());
  EXPECT_TRUE(all(log).empty());
  log.push_back(entry(0));
  EXPECT_EQ(log.inMemory(), 1u);
  expectSame(all(log), 1);
}
}  // namespace
