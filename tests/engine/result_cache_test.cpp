// The ground truth's folder of cached images: round trip, the exact file layout, misses on every
// kind of damage (never an error, never a partial read), no temporary left, unwritable folders
// reported; and the check the command line makes of a --cache folder.
#include "engine/result_cache.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

namespace penumbra::engine {
namespace {

namespace fs = std::filesystem;

class ResultCacheDir : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("penumbra-cache-" + std::to_string(::getpid()) + "-" + testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  size_t files() const {
    size_t n = 0;
    std::error_code ec;
    for (const auto& e : fs::recursive_directory_iterator(dir_, ec)) n += e.is_regular_file() ? 1 : 0;
    return n;
  }
  fs::path dir_;
};

raster::ImageFloat pattern(int w, int h) {
  raster::ImageFloat img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at(x, y) = static_cast<float>(x * 7 + y) / 64.0f;
  return img;
}

bool same(const raster::ImageFloat& a, const raster::ImageFloat& b) {
  return a.width() == b.width() && a.height() == b.height() && a.packed() == b.packed();
}

TEST_F(ResultCacheDir, RoundTripLayoutAndDamage) {
  FileResultCache cache(dir_ / "nested" / "dir");  // created on the first entry
  const uint64_t key = 0x0123456789abcdefULL;
  EXPECT_FALSE(cache.load(key, 32, 3));
  const raster::ImageFloat img = pattern(32, 3);
  ASSERT_EQ(cache.store(key, img), std::nullopt);
  const fs::path file = cache.path(key);
  EXPECT_EQ(file.filename(), "gt-0123456789abcdef.bin");
  ASSERT_TRUE(fs::is_regular_file(file));
  EXPECT_EQ(fs::file_size(file), 40u + 32u * 3u * 4u);
  EXPECT_EQ(files(), 1u);  // no temporary left
  std::optional<raster::ImageFloat> back = cache.load(key, 32, 3);
  ASSERT_TRUE(back);
  EXPECT_TRUE(same(*back, img));
  EXPECT_FALSE(cache.load(key ^ 1, 32, 3));  // another key: another file
  EXPECT_FALSE(cache.load(key, 31, 3));      // another size
  // Another key's file under this key's name: the header's key differs.
  ASSERT_EQ(cache.store(key ^ 1, img), std::nullopt);
  fs::copy_file(cache.path(key ^ 1), file, fs::copy_options::overwrite_existing);
  EXPECT_FALSE(cache.load(key, 32, 3));
  // Truncated, then one payload byte changed: misses.
  ASSERT_EQ(cache.store(key, img), std::nullopt);
  fs::resize_file(file, fs::file_size(file) - 4);
  EXPECT_FALSE(cache.load(key, 32, 3));
  ASSERT_EQ(cache.store(key, img), std::nullopt);
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(40 + 17 * 4 + 1);
    const int c = f.get();
    f.seekp(40 + 17 * 4 + 1);
    f.put(static_cast<char>(~c));
  }
  EXPECT_FALSE(cache.load(key, 32, 3));
  // A folder in the file's place: a miss, not an error.
  fs::remove(file);
  fs::create_directories(file);
  EXPECT_FALSE(cache.load(key, 32, 3));
}

TEST_F(ResultCacheDir, UnwritableFolderIsReportedAndLeavesNothing) {
  fs::create_directories(dir_);
  std::ofstream(dir_ / "file") << "x";
  FileResultCache blocked(dir_ / "file" / "sub");
  const std::optional<std::string> err = blocked.store(1, pattern(4, 4));
  ASSERT_TRUE(err);
  EXPECT_NE(err->find("cannot create"), std::string::npos) << *err;
  EXPECT_EQ(files(), 1u);
}

TEST_F(ResultCacheDir, CacheFolderCheck) {
  fs::create_directories(dir_);
  EXPECT_TRUE(checkCacheFolder(dir_.string(), "option --cache").ok());
  EXPECT_TRUE(checkCacheFolder((dir_ / "a" / "b").string(), "option --cache").ok());  // made on demand
  std::ofstream(dir_ / "file") << "x";
  const Status notDir = checkCacheFolder((dir_ / "file").string(), "option --cache");
  ASSERT_FALSE(notDir.ok());
  EXPECT_EQ(notDir.error().where, "option --cache");
  EXPECT_NE(notDir.error().what.find("not a folder"), std::string::npos) << notDir.error().line();
  const Status under = checkCacheFolder((dir_ / "file" / "sub").string(), "option --cache");
  ASSERT_FALSE(under.ok());
  EXPECT_NE(under.error().what.find("cannot be made"), std::string::npos) << under.error().line();
  EXPECT_FALSE(checkCacheFolder("", "option --cache").ok());
}

}  // namespace
}  // namespace penumbra::engine
