#include "plugslam/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "plugslam/archive.h"
#include "plugslam/eval/relations.h"
#include "plugslam/property_container.h"
#include "plugslam/solver/graph_io.h"
#include "plugslam/trajectory.h"
#include "temp_dir_test.h"

namespace fs = std::filesystem;

namespace plugslam {
namespace {

class AtomicFile : public plugslam::testing::TempDirTest {
 protected:
  AtomicFile() : TempDirTest("plugslam_atomic") {}
  std::vector<std::string> entries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename());
    std::sort(out.begin(), out.end());
    return out;
  }

  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
};

TEST_F(AtomicFile, WritesAndLeavesNoTempFile) {
  const std::string target = (dir_ / "out.txt").string();
  writeFileAtomically(target, [](std::ostream& out) { out << "first"; });
  EXPECT_EQ(slurp(target), "first");
  writeFileAtomically(target, [](std::ostream& out) { out << "second, longer content"; });
  EXPECT_EQ(slurp(target), "second, longer content");
  EXPECT_EQ(entries(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFile, NewFileGetsOrdinaryPermissions) {
  const std::string target = (dir_ / "perm.txt").string();
  writeFileAtomically(target, [](std::ostream& out) { out << "x"; });
  const mode_t mask = ::umask(022);
  ::umask(mask);
  const auto perms = fs::status(target).permissions();
  EXPECT_EQ(static_cast<mode_t>(perms) & 0777, 0666 & ~mask);
}

TEST_F(AtomicFile, AFailingWriterLeavesTheOldTargetUntouched) {
  const std::string target = (dir_ / "keep.txt").string();
  writeFileAtomically(target, [](std::ostream& out) { out << "old content"; });
  EXPECT_THROW(writeFileAtomically(target,
                                   [](std::ostream& out) {
                                     out << std::string(200000, 'x');  // beyond the buffer
                                     throw std::runtime_error("writer failed half way");
                                   }),
               std::runtime_error);
  EXPECT_EQ(slurp(target), "old content");
  EXPECT_EQ(entries(), std::vector<std::string>{"keep.txt"});
}

TEST_F(AtomicFile, AFailingWriterCreatesNoTarget) {
  const std::string target = (dir_ / "never.txt").string();
  EXPECT_THROW(writeFileAtomically(target, [](std::ostream&) { throw InputError("no"); }),
               InputError);
  EXPECT_TRUE(entries().empty());
}

TEST_F(AtomicFile, ACrashMidWriteNeverExposesAHalfWrittenTarget) {
  const std::string target = (dir_ / "crash.bin").string();
  writeFileAtomically(target, [](std::ostream& out) { out << "complete"; });
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    try {
      writeFileAtomically(target, [](std::ostream& out) {
        out << std::string(300000, 'y');
        out.flush();
        ::_exit(3);  // simulated crash: no unwinding, no cleanup
      });
    } catch (...) {
    }
    ::_exit(4);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 3);
  EXPECT_EQ(slurp(target), "complete");
  // The crash leaves only the temp file, named after the target, which a user can delete.
  for (const auto& e : entries()) {
    EXPECT_TRUE(e == "crash.bin" || e.rfind("crash.bin.tmp-", 0) == 0) << e;
  }
}

TEST_F(AtomicFile, UnwritableFolderIsAnInputError) {
  try {
    writeFileAtomically((dir_ / "missing" / "f.txt").string(), [](std::ostream& out) { out << 1; });
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
  }
}

TEST_F(AtomicFile, TextContentIsWrittenVerbatim) {
  const std::string target = (dir_ / "text.bin").string();
  const char raw[] = "line\n\0nul and \xff bytes\r\n";
  const std::string content(raw, sizeof(raw) - 1);  // with the NUL
  writeFileAtomically(target, content);
  EXPECT_EQ(slurp(target), content);
  writeFileAtomically(target, std::string());
  EXPECT_EQ(slurp(target), "");
  EXPECT_EQ(entries(), std::vector<std::string>{"text.bin"});
}

// Trajectories, relations and graphs share the one writer: an unwritable target is an InputError
// that names the target (not a temp file), and nothing is left behind.
TEST_F(AtomicFile, EveryResultWriterNamesTheTargetItCannotWrite) {
  Trajectory trajectory;
  trajectory.push_back(0.0, Eigen::Isometry3d::Identity());
  FactorGraph graph;
  const std::string missing = (dir_ / "missing").string();
  const auto expectNamed = [&](const std::string& target, const std::function<void()>& write) {
    try {
      write();
      ADD_FAILURE() << "no error writing " << target;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("'" + target + "'"), std::string::npos) << what;
    }
  };
  expectNamed(missing + "/t.tum", [&] { writeTumTrajectory(trajectory, missing + "/t.tum"); });
  expectNamed(missing + "/t.txt",
              [&] { writeKittiTrajectory(trajectory, missing + "/t.txt", ""); });
  expectNamed(missing + "/r.txt", [&] { writeRelations({}, missing + "/r.txt"); });
  expectNamed(missing + "/g.g2o", [&] { writeGraphFile(missing + "/g.g2o", graph); });
  EXPECT_TRUE(entries().empty());
  // And where they can write, they leave only their file.
  writeTumTrajectory(trajectory, (dir_ / "t.tum").string());
  writeGraphFile((dir_ / "g.g2o").string(), graph);
  EXPECT_EQ(entries(), (std::vector<std::string>{"g.g2o", "t.tum"}));
}

TEST_F(AtomicFile, ArchiveFilesRoundTripWithFormatDetection) {
  PropertyContainer c;
  c.set<double>("x", 0.1);
  c.set<std::vector<Eigen::Vector3d>>("cloud", {{1, 2, 3}, {4, 5, 6}});
  for (const char* name : {"c.bin", "c.yaml"}) {
    const std::string path = (dir_ / name).string();
    saveFile(path, c, formatForPath(path));
    PropertyContainer back;
    loadFile(path, back);
    EXPECT_EQ(back.get<double>("x"), 0.1);
    EXPECT_TRUE(back.get<std::vector<Eigen::Vector3d>>("cloud") ==
                c.get<std::vector<Eigen::Vector3d>>("cloud"));
  }
  EXPECT_EQ(slurp(dir_ / "c.bin").substr(0, 4), "PLSB");
  EXPECT_EQ(slurp(dir_ / "c.yaml").rfind("plugslam_archive: 1", 0), 0u);
  EXPECT_EQ(entries(), (std::vector<std::string>{"c.bin", "c.yaml"}));
  EXPECT_THROW(loadFile((dir_ / "absent.bin").string(), c), InputError);

  // A failing save (unregistered type) leaves the previous file intact.
  struct NoTag {
    double v = 0;
  };
  PropertyContainer bad = c;
  bad.set<NoTag>("untagged", NoTag{});
  const std::string before = slurp(dir_ / "c.bin");
  EXPECT_THROW(saveFile((dir_ / "c.bin").string(), bad, ArchiveFormat::kBinary), Error);
  EXPECT_EQ(slurp(dir_ / "c.bin"), before);
  EXPECT_EQ(entries(), (std::vector<std::string>{"c.bin", "c.yaml"}));
}

TEST(ArchiveFormatForPath, ChoosesByExtension) {
  EXPECT_EQ(formatForPath("a/b.yaml"), ArchiveFormat::kText);
  EXPECT_EQ(formatForPath("B.YML"), ArchiveFormat::kText);
  EXPECT_EQ(formatForPath("x.json"), ArchiveFormat::kText);
  EXPECT_EQ(formatForPath("x.bin"), ArchiveFormat::kBinary);
  EXPECT_EQ(formatForPath("session"), ArchiveFormat::kBinary);
}

}  // namespace
}  // namespace plugslam
