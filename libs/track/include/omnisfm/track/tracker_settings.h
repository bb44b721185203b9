#pragma once
// What the feature tracker does, in numbers. The defaults suit 1024 x 768 catadioptric images
// whose features move a few pixels per frame.

namespace omnisfm::track {

struct TrackerSettings {
  // Replenishing: new features are detected whenever fewer tracks than this are alive.
  int max_tracks = 112;

  // Detection: Shi-Tomasi corners at least this far apart and from live tracks, at least
  // quality_level times the image's strongest corner, inside the valid region shrunk by
  // rim_margin_px. They are spread over sectors and rings about the mirror's axis. Corners are
  // found on pyramid level detection_level (1: half resolution, a quarter of the work, corners
  // a few pixels across, which a 15-pixel patch holds well).
  double min_distance_px = 16;
  double quality_level = 0.01;
  int detection_level = 1;
  double rim_margin_px = 12;
  int sectors = 16, rings = 3;

  // Frame-to-frame pyramidal Lucas-Kanade (OpenCV), window lk_window x lk_window, on pyramid
  // levels prediction_level to pyramid_levels - 1. It only predicts where the refinement starts,
  // which converges from a pixel or more away, so it stops at half resolution (1), where the
  // image derivatives it needs cost a quarter of the full image's; without the refinement it
  // works down to full resolution (level 0).
  int lk_window = 11;
  int pyramid_levels = 3;
  int prediction_level = 1;
  // The forward-backward check: tracking the new position back must land this close to the old.
  double max_forward_backward_px = 0.5;

  // Refinement: the track's reference patch (2 patch_half_size + 1 wide, from the image where the
  // track started) aligned affinely into the frame, which removes the drift of frame-to-frame
  // chaining. The appearance check ends a track whose aligned patch correlates (zero-mean NCC)
  // below min_ncc, or whose refined position leaves the Lucas-Kanade one by more than
  // max_refinement_shift_px. A track also ends when a part of its patch (a half, or the centre)
  // would move the feature by more than max_misfit_px on its own (AlignmentResult::misfit_px):
  // the look has changed in a way one affine warp cannot follow, and the feature's position is
  // off by about as much. That measures what a change of shape costs: on the realistic rover the
  // error grows with it, where a patch scaled by the mirror and the approaching ground can often
  // still be placed to a tenth of a pixel. A patch scaled or sheared by more than
  // max_patch_distortion (relative change of a singular value of the affine map; rotation is
  // free) ends too: where a texture's look changes with its scale (the clean renderings'
  // procedural textures), the error grows with the scale faster than the parts' misfit shows. The
  // reference is never renewed: a renewed reference inherits the track's error at that moment,
  // so errors would add up; a feature that no longer looks like its reference ends instead, and
  // a new track starts.
  bool refine = true;  // false: positions chained by Lucas-Kanade alone (faster; drifts)
  int patch_half_size = 7;
  double image_blur_sigma = 0.5;  // Gaussian smoothing of the images patches are aligned on
  double min_ncc = 0.97;
  double max_refinement_shift_px = 1.0;
  double max_misfit_px = 0.2;
  double max_patch_distortion = 0.6;
  // A track whose step from the last frame differs by more than max_step_deviation_px from the
  // median step of the tracks within neighbourhood_radius_px of it (at least three) ends: it
  // jumped to another feature that looks alike, which the appearance checks cannot tell (on the
  // realistic lab, 12-25 px off its neighbours where followed tracks, parallax included, stay
  // within 5 px). A jolt of the camera moves the neighbours too.
  double max_step_deviation_px = 8;
  double neighbourhood_radius_px = 100;
  // Two live tracks closer than this follow the same feature: the younger one ends.
  double min_track_separation_px = 3;

  // Reacquisition: a track that ends suddenly (correlating at least sudden_loss_ncc just
  // before, as a feature an occluder covers does) is remembered for reacquire_frames frames. It
  // is looked for within reacquire_radius_px (+ reacquire_radius_growth_px per frame since the
  // loss) of where its image velocity before the loss puts it: its reference patch is aligned
  // from that prediction, from the nearest new corners and from tracks started since the loss.
  // If it aligns as well as it did before the loss (sudden_loss_ncc: a feature still partly
  // hidden would be pulled off) at exactly one place, the ORB descriptor there is within
  // max_descriptor_distance bits of the one taken where the track started, and no twin lies
  // nearby (twin_ncc), the old track
  // continues; a young track that had started on the feature ends there (what it saw before
  // stays under its own id).
  bool reacquire = true;
  double sudden_loss_ncc = 0.985;
  int reacquire_frames = 20;
  double reacquire_radius_px = 6;
  double reacquire_radius_growth_px = 1.5;
  int max_descriptor_distance = 64;
  // Repeated texture (bricks, tiles): a place found is refused when the reference, with the warp
  // found, also aligns at twin_ncc or better at a twin farther than the patch's half size from
  // it, within three search radii of it (the feature may have moved beyond the search while
  // hidden, and its twin into it) or four patch widths, whichever is more.
  double twin_ncc = 0.95;
};

}  // namespace omnisfm::track
