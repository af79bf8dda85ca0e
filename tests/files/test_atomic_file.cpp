// dlo::writeAtomically and dlo::AtomicOutput: an output is complete under its name or absent,
// and a failure leaves the previous output untouched.
#include "dlo/files/atomic_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace dlo {
namespace {

namespace fs = std::filesystem;

/// A fresh folder under the test temporary directory.
fs::path freshDir(const std::string& name) {
  const fs::path dir = fs::path(testing::TempDir()) / ("dlo_atomic_file_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(WriteAtomically, WritesTheBytesUnderTheFinalNameOnly) {
  const fs::path dir = freshDir("bytes");
  writeBytesAtomically((dir / "a.txt").string(), {'h', 'i'});
  EXPECT_EQ(slurp(dir / "a.txt"), "hi");
  EXPECT_FALSE(fs::exists(dir / "a.txt.tmp"));
}

TEST(WriteAtomically, AFailedWriteKeepsThePreviousFileAndNamesIt) {
  const fs::path dir = freshDir("failed");
  const std::string path = (dir / "a.txt").string();
  writeBytesAtomically(path, {'o', 'l', 'd'});
  try {
    writeAtomically(path, [](const std::string& temp) {
      std::ofstream(temp) << "half";
      throw std::runtime_error("disk full?\nmore");
    });
    FAIL() << "no OutputError";
  } catch (const OutputError& e) {
    EXPECT_EQ(std::string(e.what()), "cannot write '" + path + "' (disk full?).");
  }
  EXPECT_EQ(slurp(path), "old");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
}

TEST(AtomicOutput, CommitRenamesTheTemporaryFile) {
  const fs::path dir = freshDir("commit");
  AtomicOutput out((dir / "seq.rawlog").string());
  EXPECT_EQ(out.temp(), (dir / "seq.rawlog.tmp").string());
  std::ofstream(out.temp()) << "data";
  out.commit();
  EXPECT_EQ(slurp(dir / "seq.rawlog"), "data");
  EXPECT_FALSE(fs::exists(out.temp()));
}

TEST(AtomicOutput, AnAbandonedOutputIsRemovedOrKeptAsPartial) {
  const fs::path dir = freshDir("abandoned");
  {
    AtomicOutput out((dir / "empty.rawlog").string());
    std::ofstream(out.temp()) << "header";
  }
  EXPECT_TRUE(fs::is_empty(dir));
  {
    AtomicOutput out((dir / "seq").string());
    fs::create_directories(fs::path(out.temp()) / "velodyne");
    out.setKeepPartial(true);
  }
  EXPECT_TRUE(fs::is_directory(dir / "seq.partial" / "velodyne"));
  EXPECT_FALSE(fs::exists(dir / "seq"));
}

TEST(AtomicOutput, AFolderReplacesAnEmptyFolder) {
  const fs::path dir = freshDir("folder");
  fs::create_directories(dir / "seq");
  AtomicOutput out((dir / "seq").string());
  fs::create_directories(fs::path(out.temp()) / "velodyne");
  out.commit();
  EXPECT_TRUE(fs::is_directory(dir / "seq" / "velodyne"));
}

}  // namespace
}  // namespace dlo
