#include "trajectory_plots.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include "omnisfm/io/gnuplot.h"

namespace omnisfm::app {
namespace {

// x y z (m) and roll pitch yaw (deg, R = Rz(yaw) Ry(pitch) Rx(roll)) of a world_from_cam pose;
// angles continued from `previous` so that a plot does not jump by 360 degrees.
Eigen::Matrix<double, 6, 1> components(const Eigen::Isometry3d& T,
                                       const Eigen::Matrix<double, 6, 1>* previous = nullptr) {
  const Eigen::Matrix3d& R = T.linear();
  Eigen::Matrix<double, 6, 1> c;
  c << T.translation(), std::atan2(R(2, 1), R(2, 2)) * 180 / M_PI,
      std::asin(std::clamp(-R(2, 0), -1.0, 1.0)) * 180 / M_PI,
      std::atan2(R(1, 0), R(0, 0)) * 180 / M_PI;
  if (previous)
    for (int k = 3; k < 6; ++k) c[k] = (*previous)[k] + std::remainder(c[k] - (*previous)[k], 360.0);
  return c;
}

Eigen::Isometry3d aligned(const eval::Similarity& s, const Eigen::Isometry3d& T) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = s.rotation * T.linear();
  out.translation() = s.apply(T.translation());
  return out;
}

}  // namespace

bool write_trajectory_plots(const std::string& dir, const std::vector<Eigen::Isometry3d>& truth,
                            const std::vector<eval::ComparedTrajectory>& estimates) {
  const char* names[6] = {"x (m)", "y (m)", "z (m)", "roll (deg)", "pitch (deg)", "yaw (deg)"};
  std::vector<Eigen::Matrix<double, 6, 1>> true_c;
  for (const auto& T : truth)
    true_c.push_back(components(T, true_c.empty() ? nullptr : &true_c.back()));
  std::vector<std::vector<Eigen::Matrix<double, 6, 1>>> estimate_c(estimates.size());
  for (size_t e = 0; e < estimates.size(); ++e)
    for (size_t f = 0; f < truth.size(); ++f)
      estimate_c[e].push_back(components(aligned(estimates[e].alignment, estimates[e].world_from_cam[f]),
                                         &true_c[f]));
  {
    std::ofstream data(dir + "/motion.dat");
    data << "# frame truth(x y z roll pitch yaw)";
    for (const auto& e : estimates) data << ' ' << e.name << "(x y z roll pitch yaw)";
    data << '\n';
    for (size_t f = 0; f < truth.size(); ++f) {
      data << f;
      for (int k = 0; k < 6; ++k) data << ' ' << true_c[f][k];
      for (const auto& c : estimate_c)
        for (int k = 0; k < 6; ++k) data << ' ' << c[f][k];
      data << '\n';
    }
  }
  // Only the components that move, as the paper plots them.
  std::vector<int> moving;
  for (int k = 0; k < 6; ++k) {
    double lo = 1e300, hi = -1e300;
    for (const auto& c : true_c) {
      lo = std::min(lo, c[k]);
      hi = std::max(hi, c[k]);
    }
    if (hi - lo > (k < 3 ? 1e-3 : 0.05)) moving.push_back(k);
  }
  if (moving.empty()) moving.push_back(0);
  {
    std::ofstream script(dir + "/motion.gp");
    script << "set terminal pngcairo size 900," << 260 * moving.size() << "\nset output 'motion.png'\n"
           << "set multiplot layout " << moving.size() << ",1\nset key outside right\n"
           << "set xlabel 'image'\n";
    for (int k : moving) {
      script << "set ylabel '" << names[k] << "'\nplot 'motion.dat' using 1:" << 2 + k
             << " with lines lw 3 lc rgb '#999999' title 'truth'";
      for (size_t e = 0; e < estimates.size(); ++e)
        script << ", '' using 1:" << 2 + 6 * (e + 1) + k << " with points pt 7 ps 0.4 title '"
               << estimates[e].name << "'";
      script << "\n";
    }
    script << "unset multiplot\n";
    std::ofstream path(dir + "/path.gp");
    path << "set terminal pngcairo size 800,700\nset output 'path.png'\n"
         << "set size ratio -1\nset xlabel 'x (m)'\nset ylabel 'y (m)'\nset key outside bottom\n"
         << "set title 'x-y path from above (estimates aligned to the truth)'\n"
         << "plot 'motion.dat' using 2:3 with lines lw 3 lc rgb '#999999' title 'truth'";
    for (size_t e = 0; e < estimates.size(); ++e)
      path << ", '' using " << 2 + 6 * (e + 1) << ":" << 3 + 6 * (e + 1)
           << " with points pt 7 ps 0.5 title '" << estimates[e].name << "'";
    path << "\n";
  }
  return io::run_gnuplot(dir, "motion.gp") && io::run_gnuplot(dir, "path.gp");
}

}  // namespace omnisfm::app
