#include "../src/square_correlation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace omnisfm::track {
namespace {

cv::Mat textured(int rows, int cols, int seed) {
  cv::Mat image(rows, cols, CV_32FC1);
  cv::RNG rng(seed);
  rng.fill(image, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(image, image, cv::Size(0, 0), 1.5);
  return image;
}

// The zero-mean normalised correlation of the squares about a and b, in double.
double exact(const cv::Mat& image, cv::Point a, cv::Point b, int half) {
  const int n = (2 * half + 1) * (2 * half + 1);
  double mean_a = 0, mean_b = 0;
  for (int y = -half; y <= half; ++y)
    for (int x = -half; x <= half; ++x) {
      mean_a += image.at<float>(a.y + y, a.x + x) / n;
      mean_b += image.at<float>(b.y + y, b.x + x) / n;
    }
  double ab = 0, aa = 0, bb = 0;
  for (int y = -half; y <= half; ++y)
    for (int x = -half; x <= half; ++x) {
      const double va = image.at<float>(a.y + y, a.x + x) - mean_a;
      const double vb = image.at<float>(b.y + y, b.x + x) - mean_b;
      ab += va * vb;
      aa += va * va;
      bb += vb * vb;
    }
  return aa > 0 && bb > 0 ? ab / std::sqrt(aa * bb) : 0;
}

// At every place of the image: the exact value within 1e-4 (the twin search compares with 0.5), and
// OpenCV's TM_CCOEFF_NORMED (float throughout) within 1e-3.
TEST(SquareCorrelation, IsTheNormedCorrelationCoefficient) {
  const cv::Mat image = textured(60, 70, 3);
  for (const int half : {1, 2, 7}) {
    const cv::Point centre(31, 25);
    const SquareCorrelation correlation(image, centre, half);
    const cv::Rect square(centre.x - half, centre.y - half, 2 * half + 1, 2 * half + 1);
    cv::Mat scores;
    cv::matchTemplate(image, image(square), scores, cv::TM_CCOEFF_NORMED);
    double from_exact = 0, from_opencv = 0;
    for (int y = 0; y < scores.rows; ++y)
      for (int x = 0; x < scores.cols; ++x) {
        const cv::Point at(x + half, y + half);
        ASSERT_TRUE(correlation.fits(at));
        const double value = correlation.at(at);
        from_exact = std::max(from_exact, std::abs(value - exact(image, centre, at, half)));
        from_opencv = std::max(from_opencv, std::abs(value - scores.at<float>(y, x)));
      }
    EXPECT_LT(from_exact, 1e-4) << "half size " << half;
    EXPECT_LT(from_opencv, 1e-3) << "half size " << half;
    EXPECT_NEAR(correlation.at(centre), 1, 1e-6);
  }
}

// The same texture far brighter or darker, with little contrast: still itself (the sums are
// taken about each square's own level), and never beyond 1.
TEST(SquareCorrelation, AFaintTextureAtAnotherLevelIsItself) {
  const cv::Mat texture = textured(15, 15, 6);
  cv::Mat image(15, 40, CV_32FC1);
  // Contrast about 0.5 grey levels at 5, and 30 at 230.
  cv::Mat faint = image(cv::Rect(0, 0, 15, 15)), strong = image(cv::Rect(20, 0, 15, 15));
  cv::normalize(texture, faint, 4, 6, cv::NORM_MINMAX);
  cv::normalize(texture, strong, 170, 250, cv::NORM_MINMAX);
  image(cv::Rect(15, 0, 5, 15)).setTo(0);
  image(cv::Rect(35, 0, 5, 15)).setTo(0);
  for (const int half : {3, 7}) {
    const SquareCorrelation from_strong(image, cv::Point(27, 7), half);
    const SquareCorrelation from_faint(image, cv::Point(7, 7), half);
    EXPECT_NEAR(from_strong.at(cv::Point(7, 7)), 1, 1e-4) << "half size " << half;
    EXPECT_NEAR(from_faint.at(cv::Point(27, 7)), 1, 1e-4) << "half size " << half;
    EXPECT_LE(from_strong.at(cv::Point(7, 7)), 1);
    EXPECT_LE(from_faint.at(cv::Point(27, 7)), 1);
  }
}

TEST(SquareCorrelation, KnowsWhereASquareFits) {
  const cv::Mat image = textured(20, 30, 4);
  const SquareCorrelation correlation(image, cv::Point(10, 10), 3);
  EXPECT_TRUE(correlation.fits(cv::Point(3, 3)));
  EXPECT_TRUE(correlation.fits(cv::Point(26, 16)));
  EXPECT_FALSE(correlation.fits(cv::Point(2, 10)));
  EXPECT_FALSE(correlation.fits(cv::Point(27, 10)));
  EXPECT_FALSE(correlation.fits(cv::Point(10, 17)));
  EXPECT_THROW(SquareCorrelation(image, cv::Point(1, 1), 3), cv::Exception);
}

TEST(SquareCorrelation, AFlatSquareCorrelatesWithNothing) {
  cv::Mat image = textured(30, 30, 5);
  image(cv::Rect(0, 0, 10, 10)).setTo(80);
  const SquareCorrelation correlation(image, cv::Point(20, 20), 2);
  EXPECT_EQ(correlation.at(cv::Point(4, 4)), 0);
  const SquareCorrelation flat(image, cv::Point(4, 4), 2);
  EXPECT_EQ(flat.at(cv::Point(20, 20)), 0);
}

}  // namespace
}  // namespace omnisfm::track
