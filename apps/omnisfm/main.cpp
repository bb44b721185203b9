// omnisfm VERB [options]: exit status 0 on success, 2 on bad usage or bad input, 1 otherwise.

#include <glog/logging.h>

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <opencv2/core/utils/logger.hpp>

#include "image_threads.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/sfm/blas_threads.h"
#include "verbs.h"

int main(int argc, char** argv) {
  using omnisfm::io::printable_text;
  // OpenCV's and FFmpeg's own log lines ("[ERROR:0@1.7] global grfmt_...") would come before
  // omnisfm's message about the same image or video; the verbs report what OpenCV could not do.
  ::setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", 0);  // AV_LOG_QUIET, unless the user set another
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  // Ceres' warnings (a trial step that leaves the mirror is an ordinary rejected step) are not
  // news for the user: the verbs report what the solvers did.
  FLAGS_minloglevel = google::GLOG_ERROR;
  omnisfm::sfm::use_one_blas_thread();
  CLI::App app{"Shape-from-motion with catadioptric (mirror + camera) omnidirectional cameras",
               "omnisfm"};
  app.set_version_flag("--version", OMNISFM_VERSION);
  app.require_subcommand(1);
  app.footer(
      "Environment: OMNISFM_THREADS=N runs the image work (OpenCV's corner detection and "
      "tracking, the renderer) on N threads; unset, OpenCV takes one per core and the renderer "
      "two. OPENBLAS_NUM_THREADS or OMP_NUM_THREADS sets OpenBLAS's, one unless set.");
  omnisfm::app::add_project_verb(app);
  omnisfm::app::add_unproject_verb(app);
  omnisfm::app::add_simulate_verb(app);
  omnisfm::app::add_sfm_verb(app);
  omnisfm::app::add_eval_verb(app);
  omnisfm::app::add_calibrate_verb(app);
  omnisfm::app::add_detect_corners_verb(app);
  omnisfm::app::add_demo_verb(app);
  omnisfm::app::add_export_mrcal_verb(app);
  omnisfm::app::add_track_verb(app);
#ifdef OMNISFM_WITH_MRPT_PLUGIN
  omnisfm::app::add_run_verb(app);
#endif

  // CLI11 takes an unknown first word for a missing verb ("A subcommand is required").
  if (argc > 1 && argv[1][0] != '-') {
    std::string verbs;
    bool known = false;
    for (const CLI::App* verb : app.get_subcommands({})) {
      known = known || verb->get_name() == argv[1];
      verbs += (verbs.empty() ? "" : ", ") + verb->get_name();
    }
    if (!known) {
      std::cerr << "omnisfm: unknown verb '" << printable_text(argv[1]) << "' (the verbs: " << verbs
                << ")\nRun 'omnisfm --help' or 'omnisfm VERB --help' for usage.\n";
      return 2;
    }
  }
  try {
    // Checked once the command line is read, so that --help and --version answer whatever it holds.
    app.parse_complete_callback(omnisfm::app::apply_image_threads);
    app.parse(argc, argv);
    return 0;
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) return app.exit(error);  // --help, --version
    std::cerr << "omnisfm: " << printable_text(error.what()) << "\n"
              << "Run 'omnisfm --help' or 'omnisfm VERB --help' for usage.\n";
    return 2;
  } catch (const omnisfm::io::InputError& error) {
    std::cerr << "omnisfm: " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    // Other errors may quote what they read too.
    std::cerr << "omnisfm: " << printable_text(error.what()) << "\n";
    return 1;
  }
}
