#include "omnisfm/track/track_lengths.h"

#include <gtest/gtest.h>

namespace omnisfm::track {
namespace {

core::TrackObservation seen(int frame, int track) {
  core::TrackObservation o;
  o.frame = frame;
  o.track = track;
  return o;
}

TEST(TrackLengths, SpansFromFirstToLastFrameGapsIncluded) {
  // Track 7: frames 2-3 then reacquired at 9 (8 frames); track 1: 0-1 (2); track 4: 5-9 (5).
  const std::vector<core::TrackObservation> observations = {
      seen(0, 1), seen(1, 1), seen(2, 7), seen(3, 7), seen(5, 4), seen(6, 4),
      seen(7, 4), seen(8, 4), seen(9, 4), seen(9, 7)};
  const TrackLengths lengths = track_lengths(observations);
  EXPECT_EQ(lengths.tracks, 3);
  EXPECT_EQ(lengths.median_frames, 5);
  EXPECT_EQ(lengths.longest_frames, 8);
}

// As core::percentile, which the tracking figures' errors use too.
TEST(TrackLengths, EvenCountTakesTheUpperMiddle) {
  const TrackLengths lengths =
      track_lengths({seen(0, 1), seen(3, 1), seen(0, 2), seen(1, 2), seen(4, 3), seen(9, 3),
                     seen(2, 4), seen(3, 4)});
  EXPECT_EQ(lengths.tracks, 4);
  EXPECT_EQ(lengths.median_frames, 4);  // lengths 4, 2, 6, 2
  EXPECT_EQ(lengths.longest_frames, 6);
}

TEST(TrackLengths, NoTracks) {
  const TrackLengths lengths = track_lengths({});
  EXPECT_EQ(lengths.tracks, 0);
  EXPECT_EQ(lengths.median_frames, 0);
  EXPECT_EQ(lengths.longest_frames, 0);
}

}  // namespace
}  // namespace omnisfm::track
