#include "omnisfm/io/tracks_file.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>
#include <string>

#include "omnisfm/io/input_error.h"

namespace omnisfm::io {
namespace {

// One file per test and process: CTest runs the tests of this file side by side.
std::string write_file(const std::string& text) {
  const std::string path = ::testing::TempDir() + "/tracks-" +
                           ::testing::UnitTest::GetInstance()->current_test_info()->name() + "-" +
                           std::to_string(::getpid()) + ".vnl";
  std::ofstream(path) << text;
  return path;
}

TEST(TracksFile, RoundTrip) {
  const std::vector<TrackObservation> tracks = {
      {0, 3, {10.5, 20.25}}, {0, 7, {1.0 / 3, 2}}, {1, 3, {11, 21}}, {1, 7, {2, 3}}};
  const std::string path = ::testing::TempDir() + "/written.vnl";
  write_tracks(path, tracks);
  const auto back = read_tracks(path, 100, 100);
  ASSERT_EQ(back.size(), tracks.size());
  for (size_t i = 0; i < tracks.size(); ++i) {
    EXPECT_EQ(back[i].frame, tracks[i].frame);
    EXPECT_EQ(back[i].track, tracks[i].track);
    EXPECT_EQ(back[i].pixel, tracks[i].pixel);
  }
}

TEST(TracksFile, MalformedTracksNameTheLine) {
  auto expect_error = [](const std::string& text, const std::string& what, int line) {
    const std::string path = write_file(text);
    try {
      read_tracks(path, 640, 480);
      FAIL() << "no error for:\n" << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  const std::string header = "# frame track u v\n";
  expect_error(header + "1 0 5 5\n0 0 6 6\n", "must not decrease", 3);
  expect_error(header + "0 0 5 5\n0 1 - 5\n1 0 1 1\n1 1 1 1\n", "finite", 3);
  expect_error(header + "0 0 5 5\n1 0 6 6\n1 1 7 7\n", "single observation", 4);
  expect_error(header + "0 0 5 5\n1 0 6 6\n1 0 7 7\n", "twice", 4);
  expect_error(header + "0 0 5 5\n1 0 700 6\n", "outside", 3);
  expect_error(header + "0 0.5 5 5\n", "whole number from 0 to 2000000000", 2);
  expect_error("# frame track u\n0 0 5\n", "v", 0);
}

// Each frame up to the last has a pose: a frame id far beyond the others is refused, not
// allocated for (two rows at frame 1999999999 ran out of memory).
TEST(TracksFile, FrameFarBeyondThePreviousNamesTheLine) {
  auto expect_error = [](const std::string& text, int line) {
    try {
      read_tracks(write_file(text));
      FAIL() << "no error for:\n" << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find("frames without a tracked feature"), std::string::npos)
          << e.what();
    }
  };
  const std::string header = "# frame track u v\n";
  expect_error(header + "0 0 5 5\n0 1 5 5\n1999999999 0 6 6\n1999999999 1 6 6\n", 4);
  expect_error(header + "1999999999 0 6 6\n1999999999 1 6 6\n", 2);
  const int last = kMaxUntrackedFrames + 1;
  EXPECT_EQ(read_tracks(write_file(header + "0 0 5 5\n" + std::to_string(last) + " 0 6 6\n"))
                .back()
                .frame,
            last);
}

// One frame at a time, with each row's line, and the same checks as the whole file's.
TEST(TracksFile, StreamGivesAFrameAtATime) {
  const std::string path =
      write_file("# frame track u v\n0 0 5 5\n0 1 6 6\n# note\n2 1 7 7\n2 0 8 8\n1 3 1 1\n");
  TrackStream stream(path, 640, 480);
  int frame = -1;
  std::vector<TrackObservation> rows;
  ASSERT_TRUE(stream.next_frame(&frame, &rows));
  EXPECT_EQ(frame, 0);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].track, 1);
  EXPECT_EQ(stream.line(1), 3);
  // Frame 2's rows come whole; the decrease after them is found as the next frame is read ahead.
  try {
    stream.next_frame(&frame, &rows);
    FAIL() << "frame 1 after frame 2 accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 7) << e.what();
    EXPECT_NE(std::string(e.what()).find("must not decrease"), std::string::npos) << e.what();
  }
  TrackStream single(write_file("# frame track u v\n0 0 5 5\n"));
  ASSERT_TRUE(single.next_frame(&frame, &rows));
  EXPECT_FALSE(single.next_frame(&frame, &rows));
  EXPECT_TRUE(rows.empty());
}

}  // namespace
}  // namespace omnisfm::io
