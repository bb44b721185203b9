#include "omnisfm/calib/calibration_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/gnuplot.h"
#include "omnisfm/core/percentile.h"
#include "omnisfm/io/residual_vectors_plot.h"
#include "omnisfm/io/vnlog.h"

namespace omnisfm::calib {
namespace {

namespace fs = std::filesystem;

std::string fixed(double value, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

std::string general(double value, int digits = 6) {
  std::ostringstream out;
  out << std::setprecision(digits) << value;
  return out.str();
}

std::string padded(const std::string& text, std::size_t width) {
  return text.size() >= width ? text + " " : text + std::string(width - text.size(), ' ');
}

int point_id(const CalibrationView& view, int index) {
  return view.point_ids.empty() ? index : view.point_ids[index];
}

// The scale that draws the largest inlier residual about 6 % of the image width long.
double vector_scale(const CalibrationOutcome& outcome) {
  const double worst = std::max(outcome.report->final.worst_px, 1e-3);
  return std::max(1.0, io::round_down_125(0.06 * outcome.camera->image_width() / worst));
}

void write_text(const fs::path& path, const std::string& text) {
  io::write_text_atomically(path.string(), [&](std::ostream& out) { out << text; });
}

std::string residuals_script(const CalibrationOutcome& outcome, double scale) {
  io::ResidualVectorsPlot plot;
  plot.image_width = outcome.camera->image_width();
  plot.image_height = outcome.camera->image_height();
  plot.scale = scale;
  plot.title = "Residuals (projected - observed)";
  plot.x_column = 4, plot.y_column = 5, plot.du_column = 6, plot.dv_column = 7;
  plot.outlier_column = 8;
  plot.observation_dots = true;
  return io::residual_vectors_script(plot);
}

std::string histogram_script(const CalibrationOutcome& outcome) {
  const CalibrationReport& r = outcome.report->final;
  const int inliers = r.num_observations - r.num_outliers;
  const double sigma = std::max(r.rms_px, 1e-6);
  const double bin = std::max(1e-4, io::round_down_125(sigma / 4));
  const double limit = 4.5 * sigma;
  std::ostringstream gp;
  gp << "# Histogram of the inliers' residual coordinates, with the normal curve of their RMS.\n"
     << "set terminal pngcairo size 1000,650 font 'sans,11'\n"
     << "set output 'histogram.png'\n"
     << "set datafile missing '-'\n"
     << "bin = " << bin << "\n"
     << "binned(v) = bin * floor(v / bin) + bin / 2\n"
     << "sigma = " << sigma << "\n"
     << "normal(v) = " << inliers << " * bin / (sigma * sqrt(2 * pi)) * exp(-v * v / (2 * sigma "
        "* sigma))\n"
     << "set xrange [" << -limit << ":" << limit << "]\n"
     << "set xlabel 'residual coordinate (pixels)'\nset ylabel 'observations per bin'\n"
     << "set title 'Residuals of " << inliers << " inliers, bins of " << general(bin)
     << " px; the curve: a normal distribution of sigma = RMS = " << fixed(sigma, 3)
     << " px'\n"
     << "set style fill transparent solid 0.45 noborder\n"
     << "set samples 400\n"
     << "plot 'residuals.vnl' using (binned($6)):($8 == 0 ? 1 : 0) smooth frequency with boxes "
        "lc rgb '#1f4e9e' title 'du (x)', \\\n"
     << "     'residuals.vnl' using (binned($7)):($8 == 0 ? 1 : 0) smooth frequency with boxes "
        "lc rgb '#ff7f0e' title 'dv (y)', \\\n"
     << "     normal(x) with lines lw 2 lc rgb 'black' title 'normal, sigma = RMS'\n";
  return gp.str();
}

std::string uncertainty_script(const CalibrationOutcome& outcome) {
  const UncertaintyMap& map = *outcome.uncertainty;
  const int w = outcome.camera->image_width(), h = outcome.camera->image_height();
  std::ostringstream gp;
  gp << "# The projection uncertainty over the image, y down.\n"
     << "set terminal pngcairo size 1200," << static_cast<int>(1100.0 * h / w + 60)
     << " font 'sans,11'\n"
     << "set output 'uncertainty.png'\n"
     << "set datafile missing '-'\n"
     << "set size ratio -1\n"
     << "set xrange [-0.5:" << w - 0.5 << "]\n"
     << "set yrange [" << h - 0.5 << ":-0.5]\n"
     << "set xlabel 'x (pixels)'\nset ylabel 'y (pixels)'\n"
     << "set cblabel '1-sigma projection uncertainty (pixels)'\n"
     << "set palette cubehelix negative\n"
     << "set title 'Projection uncertainty (1-sigma, worst direction) of points "
     << general(map.distance_m) << " m along each pixel''s ray, fixed relative to the "
        "calibration objects'\n"
     << "set key outside bottom center horizontal\n"
     << "set style fill solid noborder\n"
     << "half = " << map.step_px / 2.0 << "\n"
     << "plot 'uncertainty.vnl' using 1:2:(half):(half):3 with boxxyerror lc palette notitle, \\\n"
     << "     'residuals.vnl' using 4:5 with points pt 7 ps 0.25 lc rgb '#2ca02c' title "
        "'observations'\n";
  return gp.str();
}

// The camera file, the inputs, the status, the solver's stages and what was estimated or held.
void write_header_and_stages(const CalibrationOutcome& outcome, std::ostream& out) {
  const StagedReport& staged = *outcome.report;
  const CalibrationReport& r = staged.final;
  out << "omnisfm calibration report\n\n";
  out << "camera file: "
      << (outcome.camera_file.empty() ? std::string("not written (see status)")
                                      : outcome.camera_file)
      << "\n";
  out << "inputs:\n";
  for (const std::string& input : outcome.inputs) out << "  " << input << "\n";
  out << "\nstatus: " << (r.converged ? "converged" : "NOT CONVERGED") << " (" << r.message
      << ")\n";

  out << "\nstages (each frees more parameters; the early ones use a Cauchy loss and the "
         "mirror's analytic continuation):\n";
  for (const StageSummary& stage : staged.stages) {
    out << "  " << padded(stage.name, 48) << padded(std::to_string(stage.iterations) + " iterations", 16)
        << "RMS " << fixed(stage.rms_px, 4) << " px" << (stage.converged ? "" : "  (stopped before converging)")
        << "\n";
  }
  out << "\nestimated (" << staged.estimated.size() << "):";
  for (const std::string& name : staged.estimated) out << " " << name;
  out << "\n";
  if (!staged.held.empty()) {
    out << "held at the starting value:\n";
    for (const HeldParameter& held : staged.held) out << "  " << held.name << ": " << held.reason << "\n";
  }

}

// The residuals over all views, per view, and the outliers.
void write_residuals(const CalibrationOutcome& outcome, std::ostream& out) {
  const CalibrationReport& r = outcome.report->final;
  const std::vector<CalibrationView>& views = *outcome.views;
  // The worst inlier, for pointing at it.
  const ObservationResidual* worst = nullptr;
  for (const ObservationResidual& o : r.residuals) {
    if (!o.outlier && o.residual.allFinite() &&
        (!worst || o.residual.norm() > worst->residual.norm()))
      worst = &o;
  }
  out << "\nresiduals (projected - observed), pixels:\n";
  out << "  RMS per coordinate over inliers: " << fixed(r.rms_px, 4)
      << "   (as the RMS of the residual vectors' lengths, OpenCV's figure: "
      << fixed(r.rms_px * std::sqrt(2.0), 4) << ")\n";
  if (worst) {
    out << "  worst inlier: " << fixed(worst->residual.norm(), 3) << " px (" << views[worst->view].name
        << ", point " << point_id(views[worst->view], worst->index) << ")\n";
  }
  out << "  residual sigma: " << fixed(r.residual_sigma_px, 4)
      << " px per coordinate (sqrt(sum of squares / (2 inliers - unknowns)))\n";
  out << "  observations: " << r.num_observations << ", outliers: " << r.num_outliers
      << " (a coordinate beyond " << general(outcome.outlier_threshold_sigma)
      << " residual sigmas, or no valid reflection)\n";

  out << "\nper view:\n  " << padded("view", 28) << padded("observations", 14) << padded("outliers", 10)
      << "RMS (px)\n";
  std::vector<int> observed(views.size(), 0), rejected(views.size(), 0);
  for (const ObservationResidual& o : r.residuals) {
    ++observed[o.view];
    if (o.outlier) ++rejected[o.view];
  }
  for (std::size_t v = 0; v < views.size(); ++v) {
    out << "  " << padded(views[v].name, 28) << padded(std::to_string(observed[v]), 14)
        << padded(std::to_string(rejected[v]), 10)
        << (v < r.view_rms_px.size() ? fixed(r.view_rms_px[v], 4) : std::string("-")) << "\n";
  }

  if (r.num_outliers > 0) {
    out << "\noutliers (view, point, observed x y, residual du dv):\n";
    for (const ObservationResidual& o : r.residuals) {
      if (!o.outlier) continue;
      const Eigen::Vector2d& pixel = views[o.view].pixels[o.index];
      out << "  " << padded(views[o.view].name, 28) << padded(std::to_string(point_id(views[o.view], o.index)), 6)
          << padded(fixed(pixel.x(), 2), 10) << padded(fixed(pixel.y(), 2), 10);
      if (o.residual.allFinite()) {
        out << padded(fixed(o.residual.x(), 3), 10) << fixed(o.residual.y(), 3) << "\n";
      } else {
        out << "no valid reflection\n";
      }
    }
  }

}

// Each parameter with its sigma, fixed, or estimated without a covariance.
void write_parameters(const CalibrationOutcome& outcome, std::ostream& out) {
  const StagedReport& staged = *outcome.report;
  const CalibrationReport& r = staged.final;
  out << "\nparameters (1-sigma from the covariance, the poses marginalised";
  if (!outcome.camera_file.empty()) out << "; also in the camera file's [omni_camera_covariance]";
  out << "):\n";
  const std::vector<std::string> names = outcome.camera->param_names();
  const Eigen::VectorXd values = outcome.camera->params();
  for (std::size_t i = 0; i < names.size(); ++i) {
    out << "  " << padded(names[i], 20) << padded(general(values[i], 9), 16);
    const auto estimated = std::find(staged.estimated.begin(), staged.estimated.end(), names[i]);
    if (estimated == staged.estimated.end()) {
      out << "fixed\n";
    } else if (r.covariance.rows() == static_cast<int>(staged.estimated.size())) {
      const int k = static_cast<int>(estimated - staged.estimated.begin());
      out << "+- " << general(std::sqrt(r.covariance(k, k)), 3) << "\n";
    } else {
      out << "estimated (no covariance)\n";
    }
  }

}

// The held-out views, when there are some.
void write_held_out(const CalibrationOutcome& outcome, std::ostream& out) {
  if (outcome.held_out) {
    const HeldOutResult& held = *outcome.held_out;
    out << "\nheld-out views (left out of the calibration; their poses solved with the camera "
           "fixed; all their observations counted):\n";
    for (std::size_t v = 0; v < held.views.size(); ++v) {
      out << "  " << padded(held.views[v], 28) << "RMS " << fixed(held.view_rms_px[v], 4) << " px\n";
    }
    out << "  RMS per coordinate over " << held.num_observations
        << " observations: " << fixed(held.rms_px, 4) << " px";
    if (held.num_unprojectable > 0) out << " (" << held.num_unprojectable << " had no valid reflection)";
    out << "\n";
  }

}

// The cross-validation's folds and pooled figure, when asked for.
void write_cross_validation(const CalibrationOutcome& outcome, std::ostream& out) {
  if (outcome.cross_validation) {
    const CrossValidation& cv = *outcome.cross_validation;
    out << "\ncross-validation, " << cv.folds.size()
        << " folds (fold f holds out every " << cv.folds.size()
        << "-th view from the f-th; the others calibrated from the same start):\n";
    for (std::size_t f = 0; f < cv.folds.size(); ++f) {
      const CrossValidationFold& fold = cv.folds[f];
      out << "  fold " << f + 1 << ": calibration RMS " << fixed(fold.calibration.final.rms_px, 4)
          << " px";
      if (fold.calibration.final.converged)
        out << ", held-out RMS " << fixed(fold.held.rms_px, 4) << " px over "
            << fold.held.num_observations << " observations of " << fold.held.views.size()
            << " views\n";
      else
        out << ", did not converge: " << fold.calibration.final.message << "\n";
    }
    out << "  pooled held-out RMS per coordinate over " << cv.num_observations
        << " observations: " << fixed(cv.pooled_rms_px, 4) << " px";
    if (cv.num_unprojectable > 0) out << " (" << cv.num_unprojectable << " had no valid reflection)";
    out << "\n";
  }

}

// The projection uncertainty over the image, when mapped.
void write_uncertainty(const CalibrationOutcome& outcome, std::ostream& out) {
  const auto summarize = [&out](const UncertaintyMap& map, const std::string& what) {
    std::vector<double> sigmas;
    for (double s : map.sigma_px) {
      if (std::isfinite(s)) sigmas.push_back(s);
    }
    out << "  " << what << ", over " << sigmas.size() << " pixels of a " << map.step_px
        << "-pixel grid that see the mirror:\n";
    if (!sigmas.empty()) {
      out << "    median " << fixed(core::percentile(sigmas, 0.5), 3) << " px, 90th percentile "
          << fixed(core::percentile(sigmas, 0.9), 3) << " px, largest "
          << fixed(*std::max_element(sigmas.begin(), sigmas.end()), 3) << " px\n";
    }
  };
  if (outcome.uncertainty) {
    out << "\nprojection uncertainty (1-sigma, worst direction) of points "
        << general(outcome.uncertainty->distance_m) << " m along each pixel's ray:\n";
    summarize(*outcome.uncertainty,
              "the point fixed relative to the calibration objects (as mrcal; uncertainty.png)");
    if (outcome.uncertainty_camera_frame) {
      summarize(*outcome.uncertainty_camera_frame,
                "the point fixed in the inner camera's frame (counts the rig's unobservable "
                "motion)");
    }
  }
}

// The files the report folder holds.
void write_files(const CalibrationOutcome& outcome, std::ostream& out) {
  out << "\nfiles: report.txt, residuals.vnl, residuals.png, histogram.png"
      << (outcome.uncertainty ? ", uncertainty.vnl, uncertainty.png" : "")
      << " (PNGs drawn by the .gp gnuplot scripts beside them)\n";
}

}  // namespace

std::string report_text(const CalibrationOutcome& outcome) {
  std::ostringstream out;
  for (const auto& write : {write_header_and_stages, write_residuals, write_parameters,
                            write_held_out, write_cross_validation, write_uncertainty, write_files})
    write(outcome, out);
  return out.str();
}

std::string write_calibration_report(const std::string& folder, const CalibrationOutcome& outcome) {
  const fs::path dir(folder);
  std::error_code error;
  fs::create_directories(dir, error);
  if (!fs::is_directory(dir)) throw std::runtime_error(folder + ": cannot create the report folder");

  write_text(dir / "report.txt", report_text(outcome));
  const std::vector<CalibrationView>& views = *outcome.views;
  io::write_text_atomically((dir / "residuals.vnl").string(), [&](std::ostream& out) {
    io::VnlogWriter writer(out, {"view", "name", "point", "x", "y", "du", "dv", "outlier"});
    writer.comment("residual (du, dv) = projected - observed (x, y), pixels");
    for (const ObservationResidual& o : outcome.report->final.residuals) {
      const Eigen::Vector2d& pixel = views[o.view].pixels[o.index];
      writer.row_texts({std::to_string(o.view), io::as_vnlog_field(views[o.view].name),
                        std::to_string(point_id(views[o.view], o.index)),
                        io::VnlogWriter::field(pixel.x()), io::VnlogWriter::field(pixel.y()),
                        io::VnlogWriter::field(o.residual.x()),
                        io::VnlogWriter::field(o.residual.y()), o.outlier ? "1" : "0"});
    }
  });
  if (outcome.uncertainty) {
    const UncertaintyMap& map = *outcome.uncertainty;
    io::write_text_atomically((dir / "uncertainty.vnl").string(), [&](std::ostream& out) {
      io::VnlogWriter writer(out, {"x", "y", "sigma"});
      writer.comment("1-sigma projection uncertainty (pixels, worst direction) of the point " +
                     general(map.distance_m) + " m along the ray of pixel (x, y)");
      for (int row = 0; row < map.rows; ++row) {
        for (int column = 0; column < map.columns; ++column) {
          writer.row({double(column * map.step_px), double(row * map.step_px),
                      map.sigma_at(column, row)});
        }
      }
    });
  }

  std::vector<std::pair<std::string, std::string>> scripts = {
      {"residuals.gp", residuals_script(outcome, vector_scale(outcome))},
      {"histogram.gp", histogram_script(outcome)}};
  if (outcome.uncertainty) scripts.push_back({"uncertainty.gp", uncertainty_script(outcome)});
  std::string failed;
  for (const auto& [name, text] : scripts) {
    write_text(dir / name, text);
    if (!io::run_gnuplot(dir.string(), name)) failed += (failed.empty() ? "" : ", ") + name;
  }
  return failed.empty() ? "" : "gnuplot could not draw " + failed + " (see its .log beside it)";
}

}  // namespace omnisfm::calib
