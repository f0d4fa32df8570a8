// Files appear whole or not at all: the temporary's name, commit, removal when not committed, and
// the signal path that removes live temporaries.
#include "engine/atomic_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

namespace penumbra::engine {
namespace {

namespace fs = std::filesystem;

class AtomicFile : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("penumbra-atomic-" + std::to_string(::getpid()) + "-" + testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
  std::string read(const fs::path& p) const {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  fs::path dir_;
};

TEST_F(AtomicFile, WritesWholeAndReplaces) {
  ASSERT_TRUE(writeFileAtomically(dir_ / "a.txt", "first").ok());
  ASSERT_TRUE(writeFileAtomically(dir_ / "a.txt", "second, longer").ok());
  EXPECT_EQ(read(dir_ / "a.txt"), "second, longer");
  EXPECT_EQ(listing(), std::vector<std::string>{"a.txt"});
}

TEST_F(AtomicFile, TemporaryIsHiddenUniqueKeepsTheExtensionAndGoesAway) {
  std::string first;
  {
    TempFile a(dir_ / "img.png"), b(dir_ / "img.png");
    first = a.path().filename().string();
    EXPECT_NE(a.path(), b.path());
    EXPECT_EQ(first[0], '.');
    EXPECT_EQ(a.path().extension(), ".png");
    EXPECT_EQ(a.path().parent_path(), dir_);
    std::ofstream(a.path()) << "x";
    std::ofstream(b.path()) << "y";
    ASSERT_TRUE(b.commit().ok());
  }
  EXPECT_EQ(listing(), std::vector<std::string>{"img.png"});  // a removed, b renamed
  EXPECT_EQ(read(dir_ / "img.png"), "y");
}

TEST_F(AtomicFile, FailuresNameTheTargetAndLeaveNothing) {
  const Status st = writeFileAtomically(dir_ / "no" / "dir" / "x.txt", "x");
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().where, (dir_ / "no" / "dir" / "x.txt").string());
  fs::create_directories(dir_ / "d.txt");  // a folder in the way of the rename
  EXPECT_FALSE(writeFileAtomically(dir_ / "d.txt", "x").ok());
  EXPECT_EQ(listing(), std::vector<std::string>{"d.txt"});
}

TEST_F(AtomicFile, SignalPathRemovesLiveTemporaries) {
  TempFile t(dir_ / "out.exr");
  std::ofstream(t.path()) << "partial";
  ASSERT_TRUE(fs::exists(t.path()));
  removeTempFilesOnSignal();
  EXPECT_FALSE(fs::exists(t.path()));
}

}  // namespace
}  // namespace penumbra::engine
