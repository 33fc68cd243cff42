// A rosbag2 folder's metadata.yaml is read through the SDK's YAML loading: an alias cycle, or a
// value of the wrong kind, is a ParseError naming metadata.yaml and the line, never a crash or a
// yaml-cpp exception escaping the reader.
#include <gtest/gtest.h>

#include <string>

#include "plugslam/errors.h"
#include "readers/ros2_bag.h"
#include "temp_dir.h"

namespace plugslam::io {
namespace {

ParseError refusal(const std::string& metadata) {
  plugslam::testing::TempDir dir("ros2_metadata");
  dir.write("bag/metadata.yaml", metadata);
  try {
    Ros2Bag bag(dir.file("bag"));
  } catch (const ParseError& e) {
    return e;
  }
  ADD_FAILURE() << "opened: " << metadata;
  return ParseError("", 0, "");
}

TEST(Ros2Metadata, AnAliasCycleIsRefusedAtItsLine) {
  const ParseError e = refusal(
      "rosbag2_bagfile_information:\n"
      "  version: 5\n"
      "  relative_file_paths: &p\n"
      "    - [a.mcap, *p]\n");
  EXPECT_NE(e.file().find("metadata.yaml"), std::string::npos) << e.file();
  EXPECT_EQ(e.line(), 4);
  EXPECT_NE(e.message().find("alias *p is inside its own anchor &p"), std::string::npos)
      << e.message();
}

TEST(Ros2Metadata, AValueOfTheWrongKindIsAParseErrorAtItsLine) {
  const ParseError e = refusal(
      "rosbag2_bagfile_information:\n"
      "  version: 5\n"
      "  storage_identifier: mcap\n"
      "  relative_file_paths:\n"
      "    - {name: a.mcap}\n");
  EXPECT_NE(e.file().find("metadata.yaml"), std::string::npos) << e.file();
  EXPECT_EQ(e.line(), 5);
}

TEST(Ros2Metadata, AFileOfAnotherToolIsNamedAsSuch) {
  const ParseError e = refusal("version: 5\n");
  EXPECT_NE(e.message().find("no rosbag2_bagfile_information"), std::string::npos) << e.message();
}

}  // namespace
}  // namespace plugslam::io
