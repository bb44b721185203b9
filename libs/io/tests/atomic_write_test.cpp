#include "omnisfm/io/atomic_write.h"

#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <ostream>
#include <stdexcept>
#include <string>

#include "omnisfm/io/input_error.h"

namespace omnisfm::io {
namespace {

namespace fs = std::filesystem;

class AtomicWriteTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("omnisfm-atomic-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    target_ = (dir_ / "out.ini").string();
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string contents() const {
    std::ifstream in(target_);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  long files() const {
    return std::distance(fs::directory_iterator(dir_), fs::directory_iterator());
  }

  fs::path dir_;
  std::string target_;
};

TEST_F(AtomicWriteTest, ReplacesTheFileWhole) {
  std::ofstream(target_) << "old\n";
  write_text_atomically(target_, [](std::ostream& out) { out << "new\n"; });
  EXPECT_EQ(contents(), "new\n");
  EXPECT_EQ(files(), 1);
}

TEST_F(AtomicWriteTest, FailureLeavesTheOldFileAndNoTemporary) {
  std::ofstream(target_) << "old\n";
  EXPECT_THROW(write_text_atomically(target_,
                                     [](std::ostream& out) {
                                       out << "half of it";
                                       throw std::runtime_error("disk full");
                                     }),
               std::runtime_error);
  EXPECT_EQ(contents(), "old\n");
  EXPECT_EQ(files(), 1);
}

TEST_F(AtomicWriteTest, TemporaryKeepsTheExtension) {
  std::string temporary;
  write_atomically((dir_ / "lens.cameramodel").string(), [&](const std::string& path) {
    temporary = path;
    std::ofstream(path) << "{}\n";
  });
  EXPECT_EQ(fs::path(temporary).extension(), ".cameramodel");
  EXPECT_EQ(fs::path(temporary).parent_path(), dir_);
  EXPECT_TRUE(fs::exists(dir_ / "lens.cameramodel"));
}

TEST_F(AtomicWriteTest, MissingFolderIsAnError) {
  EXPECT_THROW(
      write_text_atomically((dir_ / "no/such/file").string(), [](std::ostream& out) { out << 1; }),
      std::runtime_error);
}

// A killed writer's temporary goes at the next write; a running writer's stays.
TEST_F(AtomicWriteTest, TheNextWriteRemovesWhatAKilledWriterLeft) {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ASSERT_EQ(::waitpid(child, nullptr, 0), child);
  const fs::path abandoned = dir_ / ("out.tmp-" + std::to_string(child) + ".ini");
  const fs::path running = dir_ / "out.tmp-1.ini";  // init never ends
  const fs::path other = dir_ / ("other.tmp-" + std::to_string(child) + ".ini");
  for (const fs::path& path : {abandoned, running, other}) std::ofstream(path) << "half";
  write_text_atomically(target_, [](std::ostream& out) { out << "new\n"; });
  EXPECT_FALSE(fs::exists(abandoned));
  EXPECT_TRUE(fs::exists(running));
  EXPECT_TRUE(fs::exists(other));  // another file's temporaries are its own writer's business
  EXPECT_EQ(contents(), "new\n");
}

// Ids come back: a temporary whose id a task started after it was written holds is abandoned.
TEST_F(AtomicWriteTest, AnIdReusedSinceIsNotTheWriter) {
  const pid_t child = ::fork();
  if (child == 0) {
    ::pause();
    ::_exit(0);
  }
  ASSERT_GT(child, 0);
  const fs::path abandoned = dir_ / ("out.tmp-" + std::to_string(child) + ".ini");
  std::ofstream(abandoned) << "half";
  const ::timespec an_hour_ago[2] = {{::time(nullptr) - 3600, 0}, {::time(nullptr) - 3600, 0}};
  ASSERT_EQ(::utimensat(AT_FDCWD, abandoned.c_str(), an_hour_ago, 0), 0);
  write_text_atomically(target_, [](std::ostream& out) { out << "new\n"; });
  ::kill(child, SIGKILL);
  ::waitpid(child, nullptr, 0);
  EXPECT_FALSE(fs::exists(abandoned)) << "the child started after the file was written";
  EXPECT_EQ(contents(), "new\n");
}

// A folder replaced whole: its new files only, and what a killed writer left beside it gone
// (every writing verb and `simulate` write their folders so).
TEST_F(AtomicWriteTest, AFolderIsReplacedWholeAndAKilledWritersFolderGoes) {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ASSERT_EQ(::waitpid(child, nullptr, 0), child);
  const fs::path folder = dir_ / "result";
  fs::create_directories(folder);
  std::ofstream(folder / "old.txt") << "old\n";
  const fs::path partial = dir_ / (".result.partial-" + std::to_string(child));
  const fs::path previous = dir_ / (".result.previous-" + std::to_string(child));
  fs::create_directories(partial);
  fs::create_directories(previous);
  write_folder_atomically(folder.string(), [](const std::string& into) {
    std::ofstream(fs::path(into) / "new.txt") << "new\n";
  });
  EXPECT_FALSE(fs::exists(partial));
  EXPECT_FALSE(fs::exists(previous));
  EXPECT_TRUE(fs::exists(folder / "new.txt"));
  EXPECT_FALSE(fs::exists(folder / "old.txt"));
  EXPECT_EQ(files(), 1);

  EXPECT_THROW(write_folder_atomically(folder.string(),
                                       [](const std::string&) { throw std::runtime_error("x"); }),
               std::runtime_error);
  EXPECT_TRUE(fs::exists(folder / "new.txt"));
  EXPECT_EQ(files(), 1);
  EXPECT_THROW(write_folder_atomically((dir_ / "missing" / "result").string(),
                                       [](const std::string&) {}),
               InputError);
}

}  // namespace
}  // namespace omnisfm::io
