// K-fold cross-validation on synthetic boards seen through the hyperbolic rig: every view is held
// out once, and with the right model the views held out fit as well as the noise allows.

#include "omnisfm/calib/cross_validation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "synthetic_boards.h"

namespace omnisfm::calib {
namespace {

constexpr double kNoisePx = 0.2;

TEST(CrossValidation, EveryViewHeldOutOnceAndTheRightModelGeneralises) {
  const std::vector<CalibrationView> views =
      testing::board_views(testing::true_hyperbolic_rig(), 10, kNoisePx, 3);
  ASSERT_EQ(views.size(), 10u);
  StagedSettings settings;
  settings.groups = {"mirror-pose", "intrinsics", "mirror-shape"};
  std::vector<int> done;
  const CrossValidation cv = cross_validate(testing::nominal_hyperbolic_rig(), views, settings, 5,
                                            [&](int fold) { done.push_back(fold); });
  EXPECT_EQ(done, (std::vector<int>{0, 1, 2, 3, 4}));
  ASSERT_EQ(cv.folds.size(), 5u);
  EXPECT_EQ(cv.folds_not_converged, 0);

  std::vector<std::string> held;
  for (std::size_t f = 0; f < cv.folds.size(); ++f) {
    const CrossValidationFold& fold = cv.folds[f];
    ASSERT_TRUE(fold.calibration.final.converged) << fold.calibration.final.message;
    // Fold f holds out views f and f + 5.
    ASSERT_EQ(fold.held.views.size(), 2u);
    EXPECT_EQ(fold.held.views[0], views[f].name);
    EXPECT_EQ(fold.held.views[1], views[f + 5].name);
    held.insert(held.end(), fold.held.views.begin(), fold.held.views.end());
  }
  std::sort(held.begin(), held.end());
  std::vector<std::string> names;
  for (const CalibrationView& v : views) names.push_back(v.name);
  std::sort(names.begin(), names.end());
  EXPECT_EQ(held, names);

  // Every corner of every view counted once. A held-out view's residuals are the noise less what
  // its 6 pose unknowns absorb of 84, plus the camera's error from 8 views: measured 0.201 px.
  EXPECT_EQ(cv.num_observations + cv.num_unprojectable, 420);
  EXPECT_EQ(cv.num_unprojectable, 0);
  EXPECT_GT(cv.pooled_rms_px, 0.9 * kNoisePx);
  EXPECT_LT(cv.pooled_rms_px, 1.15 * kNoisePx);
}

TEST(CrossValidation, FoldsMustLeaveViewsOnBothSides) {
  const std::vector<CalibrationView> views =
      testing::board_views(testing::true_hyperbolic_rig(), 4, kNoisePx, 3);
  const StagedSettings settings;
  EXPECT_THROW(cross_validate(testing::nominal_hyperbolic_rig(), views, settings, 1),
               std::invalid_argument);
  EXPECT_THROW(cross_validate(testing::nominal_hyperbolic_rig(), views, settings, 5),
               std::invalid_argument);
}

TEST(CrossValidation, HoldOutViewsKeepsTheRestInOrder) {
  const std::vector<CalibrationView> views =
      testing::board_views(testing::true_hyperbolic_rig(), 6, kNoisePx, 3);
  const ViewPartition p = hold_out_views(views, 2);
  ASSERT_EQ(p.held.size(), 2u);
  ASSERT_EQ(p.kept.size(), 4u);
  EXPECT_EQ(p.held[0].name, views[1].name);  // spread_views(6, 2) = {1, 4}
  EXPECT_EQ(p.held[1].name, views[4].name);
  EXPECT_EQ(p.kept[0].name, views[0].name);
  EXPECT_EQ(p.kept[3].name, views[5].name);
  EXPECT_THROW(hold_out_views(views, 6), std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::calib
