// Every export is all-or-nothing: failures name the file and leave no partial output.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "../temp_dir.h"
#include "dlo/export/export_all.h"
#include "dlo/export/pose_graph_export.h"
#include "dlo/export/simple_map_export.h"
#include "dlo/export/trajectory_export.h"
#include "dlo/files/atomic_file.h"
#include "synthetic_map.h"

namespace fs = std::filesystem;

namespace {

dlo::SlamMap smallMap() {
  dlo::SlamMap map = dlo::test::makeSyntheticMap();
  for (auto& kf : map.keyframes) kf.cloud.resize(50);  // content is irrelevant here
  return map;
}

std::string readAll(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST(AtomicExport, MissingFolderIsNamedAndNothingIsCreated) {
  dlo::test::TempDir folder("missing");
  const std::string dir = folder.path("does/not/exist");
  try {
    dlo::exportAll(smallMap(), dir);
    FAIL() << "no exception";
  } catch (const dlo::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir));
  EXPECT_TRUE(fs::is_empty(folder.dir()));
}

TEST(AtomicExport, FolderThatIsAFileIsRejected) {
  dlo::test::TempDir folder("file");
  std::ofstream(folder.path("plain")) << "x";
  EXPECT_THROW(dlo::exportAll(smallMap(), folder.path("plain")), dlo::OutputError);
}

TEST(AtomicExport, ReadOnlyFolderIsRejectedWithoutPartialFiles) {
  if (::geteuid() == 0) GTEST_SKIP() << "root can write into read-only folders";
  dlo::test::TempDir folder("readonly");
  fs::permissions(folder.dir(), fs::perms::owner_read | fs::perms::owner_exec);
  EXPECT_THROW(dlo::exportAll(smallMap(), folder.dir().string()), dlo::OutputError);
  fs::permissions(folder.dir(), fs::perms::owner_all);
  EXPECT_TRUE(fs::is_empty(folder.dir()));
}

TEST(AtomicExport, EachWriterNamesItsFileAndLeavesNoTemporary) {
  dlo::test::TempDir folder("writers");
  const dlo::SlamMap map = smallMap();
  const std::string dir = folder.path("gone");
  const std::vector<std::pair<std::string, std::function<void(const std::string&)>>> writers = {
      {"trajectory.tum", [&](const std::string& p) { dlo::exportTrajectoryTum(map, p); }},
      {"trajectory.kitti", [&](const std::string& p) { dlo::exportTrajectoryKitti(map, p); }},
      {"keyframes.graph", [&](const std::string& p) { dlo::exportPoseGraph(map, p); }},
      {"map.simplemap", [&](const std::string& p) { dlo::exportSimpleMap(map, p); }},
  };
  for (const auto& [name, write] : writers) {
    const std::string path = dir + "/" + name;
    try {
      write(path);
      ADD_FAILURE() << name << ": no exception";
    } catch (const dlo::OutputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(fs::is_empty(folder.dir()));
}

TEST(AtomicExport, FailedWriteKeepsThePreviousFile) {
  dlo::test::TempDir folder("keep");
  const std::string path = folder.path("out.txt");
  std::ofstream(path) << "previous";
  EXPECT_THROW(dlo::writeAtomically(path,
                                    [](const std::string& temp) {
                                      std::ofstream(temp) << "half";
                                      throw std::runtime_error("interrupted");
                                    }),
               dlo::OutputError);
  EXPECT_EQ(readAll(path), "previous");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  dlo::writeAtomically(path, [](const std::string& temp) { std::ofstream(temp) << "new"; });
  EXPECT_EQ(readAll(path), "new");
}

TEST(AtomicExport, EmptyMapStillExportsEveryFile) {
  dlo::test::TempDir folder("empty");
  dlo::ExportOptions options;
  options.render = false;
  const dlo::ExportReport report = dlo::exportAll(dlo::SlamMap(), folder.dir().string(), options);
  EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
  // trajectory (2), graph, simplemap, height map (3), occupancy grid (3), PLY, scene.
  EXPECT_EQ(report.written.size(), 12u);
}
