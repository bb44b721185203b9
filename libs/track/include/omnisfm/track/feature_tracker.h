#pragma once
// The tracker: features followed from image to image, as the paper's first stage.
//
// Per image: pyramidal Lucas-Kanade (OpenCV) from the previous image predicts every live track,
// starting from its last image velocity, down to half resolution (full resolution without the
// refinement); tracking that prediction back must return to the old position (the
// forward-backward check). The track's reference patch, taken where the track
// started, is then aligned affinely at the prediction (patch_alignment.h): the track's position
// comes from that alignment, so it does not drift, and a poor correlation or a large correction
// ends the track (the appearance check). A look that changes steadily renews the reference a few
// times (TrackerSettings::max_renewals). Tracks leaving the trackable region end; of two tracks
// on one feature the younger ends. Tracks that end suddenly are remembered and looked for again
// near where their image motion predicts them (tracker_settings.h, reacquisition); found, they
// continue under their old id. Once a few of max_tracks are missing
// (TrackerSettings::detect_at_missing), new corners start new tracks, spread over the image,
// where the images' noise lets their patch be followed (TrackerSettings::min_followable_ncc).

#include <Eigen/Core>
#include <deque>
#include <opencv2/core.hpp>
#include <vector>

#include "omnisfm/core/track_observation.h"
#include "omnisfm/track/feature_descriptor.h"
#include "omnisfm/track/feature_detector.h"
#include "omnisfm/track/patch_alignment.h"
#include "omnisfm/track/tracker_settings.h"

namespace omnisfm::track {

class StepNeighbourhoods;

using core::TrackPixel;

// Why tracks ended, and how many started, over the whole sequence.
struct TrackerStatistics {
  int frames = 0;
  int started = 0;
  int too_faint = 0;  // corners not started: the noise leaves their patch below min_followable_ncc
  int renewed = 0;    // references taken anew (TrackerSettings::max_renewals)
  int smoothed_anew = 0;  // references' templates matched to their patch's scale (match_blur)
  int reacquired = 0;
  // Of those, found again in the frame that lost them: their tracks show no gap.
  int reacquired_at_once = 0;
  // Lost tracks forgotten: found again where their look repeats nearby (twin_ncc).
  int forgotten_among_twins = 0;
  int lost = 0;              // Lucas-Kanade found nothing
  int forward_backward = 0;  // failed the forward-backward check
  int appearance = 0;        // failed the appearance check
  int misfit = 0;            // its patch's parts pulled apart beyond max_misfit_px
  int reshaped = 0;          // scaled or sheared beyond max_patch_distortion
  int jumped = 0;            // its step far from its neighbours' (max_step_deviation_px)
  int left_region = 0;
  int duplicate = 0;
};

class FeatureTracker {
 public:
  // region: CV_8UC1, 255 where tracks may be (valid_region_mask with rim_margin_px); not empty.
  FeatureTracker(const cv::Mat& region, const TrackerSettings& settings);

  // Tracks into the next image (CV_8UC1, the region's size) and returns the tracks seen in it.
  std::vector<TrackPixel> track(const cv::Mat& full_image);

  const TrackerStatistics& statistics() const { return statistics_; }
  int num_live_tracks() const { return static_cast<int>(live_.size()); }
  // The images' noise as estimated so far (grey levels of the blurred images patches are aligned
  // on; 0 before any track was followed): TrackerSettings::min_followable_ncc.
  double noise() const { return noise_; }

 private:
  struct Track {
    int id = 0;
    int first_frame = 0, last_frame = 0;
    Eigen::Vector2d position{0, 0};
    Eigen::Vector2d velocity{0, 0};       // pixels per frame, over the last step
    std::vector<Eigen::Vector2d> recent;  // the last few positions, oldest first
    AffineWarp warp;                      // the reference patch in the latest image
    // The point the track reports, in the reference's coordinates (the feature is at 0): at
    // first the reference's best located point (ReferencePatch::best_located_offset).
    Eigen::Vector2d reported{0, 0};
    // The patch's change of shape in the image over the last step (warp.A then, as a map from
    // the image before): the next step's is predicted to be the same.
    Eigen::Matrix2d shape_step = Eigen::Matrix2d::Identity();
    ReferencePatch reference;
    int renewals = 0;  // of the reference (TrackerSettings::max_renewals)
    double ncc = 1;                  // of the latest alignment
    FeatureSurroundings first_look;  // around the feature where its reference was last taken
    Descriptor descriptor;           // of first_look, once the track is lost

    // Whether the track has been seen in enough frames (five) for its image motion before its
    // last frames to be known, and where that motion puts it at `frame`.
    bool moved_long_enough() const;
    Eigen::Vector2d predicted(int frame) const;
  };

  // The blurred float image patches are aligned on.
  cv::Mat alignment_image(const cv::Mat& image) const;
  // Starts a track at `at` of the current frame; false when there is no texture to follow.
  bool start_track(const cv::Point2f& at, int id);
  void follow_live_tracks();
  // The live tracks' steps this frame, by where they began (neighbourhood_radius_px).
  StepNeighbourhoods live_steps() const;
  // Ends the tracks whose step this frame left their neighbours' (max_step_deviation_px).
  void end_jumped_tracks();
  void remove_duplicates();
  // Reacquires lost tracks, then starts new ones from fresh corners up to max_tracks.
  void replenish();
  // Lost tracks recognised near their predicted position continue; the corners near where
  // they are found are removed, and their positions added to `reacquired`.
  void reacquire(std::vector<cv::Point2f>* corners, std::vector<cv::Point2f>* reacquired);
  // Where a lost track may be, and the young track there, if any.
  struct Place {
    AffineWarp warp;
    int young = -1;  // index into live_, or -1
    double ncc = 0;
  };
  // Where to start looking for lost track t within `radius` of `predicted`: the prediction, the
  // nearest unused corner, and the nearest track started since the loss and not yet ended (the
  // feature coming out from behind an occluder may have been taken for a new one).
  std::vector<Place> reacquisition_starts(const Track& t, const Eigen::Vector2d& predicted,
                                          double radius, const std::vector<cv::Point2f>& corners,
                                          const std::vector<bool>& corner_used,
                                          const std::vector<bool>& young_ended) const;
  // Every distinct place near the prediction where t's reference aligns as well as it did
  // before the loss; more than one is repeated texture.
  std::vector<Place> places_found(const Track& t, const std::vector<Place>& starts,
                                  const Eigen::Vector2d& predicted, double radius) const;
  // Whether t is the feature at `place`: its descriptor agrees (else kNot) and no twin lies
  // around (else kAmongTwins).
  enum class Recognition { kRecognised, kNot, kAmongTwins };
  Recognition recognise(const Track& t, const Place& place, double radius) const;
  // Whether t's reference, found at `found`, also aligns at a twin within `radius` of it:
  // TrackerSettings::twin_ncc.
  bool repeated_nearby(const Track& t, const AffineWarp& found, double radius) const;
  // Counts the end in *counter; a track that may come back (not one that left the region or
  // changed its look) is remembered for reacquisition.
  void end_track(size_t index, int* counter, bool may_return = true);
  // Keeps the live tracks for whose index keep(i) is true, in order, moved to the front in
  // place; keep(i) may end track i.
  template <typename Keep>
  void keep_live_tracks(Keep keep);
  bool in_region(const Eigen::Vector2d& p) const;
  // The pyramids start at this level (0: full resolution).
  int lucas_kanade_finest_level() const;

  // All work is done in the region's bounding box (with a border for the pyramid and the
  // descriptors): positions inside the tracker are relative to its corner.
  cv::Size image_size_;
  cv::Rect bounds_;
  cv::Mat region_;
  TrackerSettings settings_;
  FeatureDetector detector_;
  int frame_ = -1;
  // The images' noise, grey levels of the alignment image: from the live tracks' alignment
  // residuals (each holds two looks' noise), 0 until tracks have been followed.
  double noise_ = 0;
  void estimate_noise(std::vector<double> residuals);
  int next_id_ = 0;
  std::vector<cv::Mat> previous_pyramid_, pyramid_;
  cv::Mat image_, aligned_image_;  // the current frame: grey, and for alignment
  std::vector<Track> live_;
  std::deque<Track> lost_;  // recently ended, oldest first
  TrackerStatistics statistics_;
};

}  // namespace omnisfm::track
