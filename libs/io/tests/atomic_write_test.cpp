#include "omnisfm/io/atomic_write.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

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
  write_folder_atomically(folder.string(), [](const std::string& into) {
    std::ofstream(fs::path(into) / "old.txt") << "old\n";
  });
  ASSERT_TRUE(fs::exists(folder / kWrittenFolderMarker));
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

// A folder is replaced whole only where nothing is lost: an earlier result, or nothing. A folder of
// other files, one holding what the run reads, a file, an empty path and the root are refused,
// before any work and leaving everything as it was.
TEST_F(AtomicWriteTest, AFolderIsReplacedOnlyWhereNothingIsLost) {
  const fs::path own = dir_ / "photos";
  fs::create_directories(own);
  std::ofstream(own / "holiday.jpg") << "jpeg\n";
  const auto refused = [](const std::string& dir, const std::vector<std::string>& inputs = {}) {
    try {
      check_folder_replaceable(dir, inputs);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(refused(own.string()).find("holiday.jpg"), std::string::npos);
  bool wrote = false;
  EXPECT_THROW(write_folder_atomically(own.string(), [&](const std::string&) { wrote = true; }),
               InputError);
  EXPECT_FALSE(wrote);
  EXPECT_TRUE(fs::exists(own / "holiday.jpg"));
  // The same folder by other names.
  EXPECT_NE(refused(own.string() + "/"), "");
  EXPECT_NE(refused((own / ".").string()), "");
  EXPECT_EQ(folder_path(own.string() + "//"), folder_path(own.string()));

  const fs::path result = dir_ / "result";
  write_folder_atomically(result.string(), [](const std::string& into) {
    std::ofstream(fs::path(into) / "tracks.vnl") << "# frame track u v\n";
  });
  EXPECT_EQ(refused(result.string()), "");
  EXPECT_EQ(refused(result.string() + "/"), "");
  const std::string input = (result / "tracks.vnl").string();
  EXPECT_NE(refused(result.string(), {"", input}).find("holds the input " + input),
            std::string::npos);
  EXPECT_NE(refused(result.string(), {result.string()}), "");
  EXPECT_EQ(refused(result.string(), {(dir_ / "resulting.vnl").string()}), "");

  const fs::path empty = dir_ / "empty";
  fs::create_directories(empty);
  EXPECT_EQ(refused(empty.string()), "");
  EXPECT_EQ(refused((dir_ / "new").string()), "");
  EXPECT_NE(refused((own / "holiday.jpg").string()).find("exists and is not a folder"),
            std::string::npos);
  EXPECT_NE(refused((dir_ / "missing" / "new").string()).find("missing does not exist"),
            std::string::npos);
  EXPECT_NE(refused((own / "holiday.jpg" / "new").string()).find("holiday.jpg is not a folder"),
            std::string::npos);
  EXPECT_NE(refused(""), "");
  EXPECT_NE(refused("/"), "");
  // The working folder, empty or not, would be swapped from under the shell in it; a link would
  // be replaced by a folder of its own.
  const fs::path working = fs::current_path();
  fs::current_path(empty);
  EXPECT_NE(refused(".").find("is the working folder"), std::string::npos);
  EXPECT_NE(refused("..").find("is the working folder"), std::string::npos);
  fs::current_path(working);
  fs::create_directory_symlink(empty, dir_ / "link");
  EXPECT_NE(refused((dir_ / "link").string()).find("is a symbolic link"), std::string::npos);
  // A name the temporary beside it could not extend.
  EXPECT_NE(refused((dir_ / std::string(201, 'a')).string()).find("bytes long; at most 200"),
            std::string::npos);
  EXPECT_EQ(refused((dir_ / std::string(200, 'a')).string()), "");
}

// A file written over is a regular file: a pipe, a device or a link would be replaced by one.
TEST_F(AtomicWriteTest, OnlyARegularFileIsWrittenOver) {
  const fs::path pipe = dir_ / "pipe";
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  fs::create_symlink(target_, dir_ / "link.ini");
  for (const fs::path& special : {pipe, dir_ / "link.ini", dir_})
    EXPECT_THROW(write_text_atomically(special.string(), [](std::ostream& out) { out << "x"; }),
                 InputError)
        << special;
  EXPECT_TRUE(fs::is_fifo(pipe));
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.ini"));
  write_text_atomically(target_, [](std::ostream& out) { out << "x\n"; });
  write_text_atomically(target_, [](std::ostream& out) { out << "y\n"; });
  EXPECT_EQ(contents(), "y\n");
}

}  // namespace
}  // namespace omnisfm::io
