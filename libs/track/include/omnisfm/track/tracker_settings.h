#pragma once
// What the feature tracker does, in numbers. The defaults suit 1024 x 768 catadioptric images
// whose features move a few pixels per frame.

namespace omnisfm::track {

struct TrackerSettings {
  // Replenishing: new features are detected once detect_at_missing of max_tracks are missing, or an
  // eighth of max_tracks where that is fewer (at least one). A detection costs about as much as
  // following every track, and on the realistic rover a frame loses about four: detected only once
  // eight were missing, the tracker took 1.38 ms per frame where it took 1.78, with 109 tracks
  // alive on average where it kept 112, the median track as long (28-31 frames, seeds 1-3) and its
  // error as small, but half the reacquisitions (which start from new corners too: 12, 9, 11 where
  // there were 24, 17, 16, none wrong). 1: whenever one is missing.
  int max_tracks = 112;
  int detect_at_missing = 8;

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
  // A corner starts a track only where the image noise leaves its patch an expected correlation
  // with itself of at least min_followable_ncc: 1 - noise^2 / contrast^2 for two noisy looks at
  // it (contrast: the patch's weighted standard deviation; the noise is estimated from the live
  // tracks' alignment residuals). A fainter patch fails the appearance check (min_ncc) within a
  // frame or two however well it is followed: on the realistic rover, more than half of the
  // tracks that ended on it did so at an age of one or two frames, with a median contrast of 8.5
  // grey levels against 17 for the others. The noise estimate is approximate: the patches'
  // misfit raises it, and it reads low by about a third where the misfit is small (the
  // template, smoothed as bilinear sampling smooths, keeps half its look's noise variance, and
  // sampling smooths the other look's), as the figures here were measured. While fewer than half of
  // max_tracks are alive, faint corners start tracks too. 0: every corner with texture starts a
  // track.
  double min_followable_ncc = 0.99;

  // Frame-to-frame pyramidal Lucas-Kanade (OpenCV), window lk_window x lk_window, on pyramid
  // levels prediction_level to pyramid_levels - 1. It only predicts where the refinement starts,
  // which converges from a pixel or more away, so it stops at half resolution (1), where the
  // image derivatives it needs cost a quarter of the full image's; without the refinement it
  // works down to full resolution (level 0).
  int lk_window = 11;
  int pyramid_levels = 3;
  int prediction_level = 1;
  // The forward-backward check: tracking the new position back must land this close to the old.
  // It guards the plain tracker (refine false). With the refinement it runs only where
  // forward_backward_with_refinement is set: it changes nothing that was measured there (the
  // refinement's own checks end what it would: on the realistic lab, crane and rover, seeds 1-5,
  // the same stray tracks but one and 95th percentiles within 0.012 px of those with it, and no
  // reacquisition wrong) and took a sixteenth of the tracker's time.
  double max_forward_backward_px = 0.5;
  bool forward_backward_with_refinement = false;

  // Refinement: the track's reference patch (2 patch_half_size + 1 wide, from the image where the
  // track started, or where it was last renewed: max_renewals) aligned affinely into the frame,
  // which removes the drift of frame-to-frame chaining. The appearance check ends a track whose aligned patch correlates (zero-mean NCC)
  // below min_ncc, or whose refined position leaves the Lucas-Kanade one by more than
  // max_refinement_shift_px. A track also ends when a part of its patch (a half, or the centre)
  // would move the feature by more than max_misfit_px on its own (AlignmentResult::misfit_px):
  // the look has changed in a way one affine warp cannot follow, and the feature's position is
  // off by about as much. That measures what a change of shape costs: on the realistic rover the
  // error grows with it, where a patch scaled by the mirror and the approaching ground can often
  // still be placed to a tenth of a pixel. A patch scaled or sheared by more than
  // max_patch_distortion (relative change of a singular value of the affine map; rotation is
  // free) ends too: where a texture's look changes with its scale (the clean renderings'
  // procedural textures), the error grows with the scale faster than the parts' misfit shows.
  bool refine = true;  // false: positions chained by Lucas-Kanade alone (faster; drifts)
  int patch_half_size = 7;
  double image_blur_sigma = 0.5;  // Gaussian smoothing of the images patches are aligned on
  // The camera's own blur before that smoothing (a Gaussian's sigma, pixels: its optics and its
  // pixels' area). An image blurs what it shows by the same amount at any scale, so a patch the
  // image shrinks shows its texture more blurred than its reference, and one it magnifies
  // sharper; the reference's template is smoothed to match (ReferencePatch::match_blur), for
  // which the images' whole blur is needed (`omnisfm track --camera-blur`). The realistic
  // renderings': a defocus of 0.6 px and the pixels' area, 0.66; the clean ones' 0.29
  // (sim::ImagingSettings::blur_px).
  double camera_blur_px = 0.66;
  // The aligned images' whole blur (variance, px^2 along each axis): the camera's and the
  // smoothing's. The smoothing counts as its sigma^2, 0.25 px^2, though its three taps blur by
  // 0.213: the renderings' own blur is known no closer (their pixels' area taken as 1/12), and
  // with 0.213 the realistic lab's 95th percentile was 0.290 / 0.278 / 0.258 / 0.271 / 0.312 px
  // at seeds 1-5, against 0.285 / 0.270 / 0.265 / 0.266 / 0.299.
  double blur_variance() const {
    return camera_blur_px * camera_blur_px + image_blur_sigma * image_blur_sigma;
  }
  double min_ncc = 0.97;
  double max_refinement_shift_px = 1.0;
  double max_misfit_px = 0.2;
  double max_patch_distortion = 0.6;
  // Renewal: a track whose look has come halfway to where those checks would end it (its
  // correlation below (1 + min_ncc) / 2, or its patch distorted by more than half
  // max_patch_distortion) while its parts still agree within half max_misfit_px takes its
  // reference anew where it now is, at most max_renewals times (so max_patch_distortion and
  // min_ncc hold against the latest reference, not the first). A renewed reference inherits the
  // track's error at that moment, so the errors add up as renewals come, hence the limit. Over a
  // surface coming closer under the rig the look changes steadily, and with a fixed reference
  // the realistic rover's tracks lasted 16 frames at the median; renewed up to 4 times, 29-31
  // (seeds 1-3), their error's 95th percentile 0.18 -> 0.22 px, none beyond 1 px. 0: never.
  int max_renewals = 4;
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
  // max_descriptor_distance bits of the one taken with its reference, and no twin lies
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
  // hidden, and its twin into it) or four patch widths, whichever is more. The lost track is then
  // forgotten: its texture stays repeated as the camera moves, and on the realistic lab, where
  // the same tracks were searched again up to 16 times, searching cost 60 % of the tracker's time
  // (2.9-3.4 ms per frame where it took 4.3-4.6, build/bench/track_truth; 1-2 reacquisitions per
  // sequence where there were 3-6, none wrong, seeds 1-3).
  double twin_ncc = 0.95;
};

}  // namespace omnisfm::track
