// omnisfm-slam: an MRPT SLAM application built on omnisfm's estimator, written the way MRPT's own
// kf-slam and icp-slam are, to copy into an existing SLAM app. It holds OmniSfmEstimator as a
// mrpt::slam::CMetricMapBuilder*, reads a rawlog of either format with
// CRawlog::getActionObservationPairOrObservation, and saves what it built as MRPT does: a
// .3Dscene every --scene-every camera frames and at the end (the robot's path, axes along it, the
// points: scene_file.h), the robot's path as a TUM trajectory, and a top view. With --live and a display, a
// CDisplayWindow3D shows the scene as it grows (--screenshot saves its last image).
//
//   omnisfm-slam DATASET.rawlog --out DIR [--config omnisfm.ini] [--scene-every N] [--live]

#include <CLI/CLI.hpp>
#include <glog/logging.h>
#include <mrpt/gui/CDisplayWindow3D.h>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/slam/CMetricMapBuilder.h>
#include <mrpt/system/os.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <thread>
#include <vector>

#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/mrpt_plugin/omni_sfm_estimator.h"
#include "omnisfm/mrpt_plugin/rawlog_input.h"
#include "omnisfm/mrpt_plugin/scene.h"
#include "omnisfm/sfm/blas_threads.h"

namespace {

// What has been built so far: the robot's path and the estimator's points, as omnisfm run's
// scene.3Dscene shows a result (scene_file.h).
mrpt::opengl::COpenGLScene::Ptr scene_of(const std::vector<mrpt::poses::CPose3D>& path,
                                         const omnisfm::mrpt_plugin::OmniSfmEstimator& estimator) {
  omnisfm::mrpt_plugin::SceneContents contents;
  for (const mrpt::poses::CPose3D& pose : path) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.matrix() = pose.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen();
    contents.world_from_cam.push_back(T);
  }
  contents.points = estimator.points();
  return omnisfm::mrpt_plugin::make_scene(contents);
}

bool is_uniform(const mrpt::img::CImage& image) {
  if (image.isEmpty()) return true;
  const mrpt::img::CImage grey = image.grayscale();
  const uint8_t first = grey.at<uint8_t>(0, 0);
  for (int y = 0; y < grey.getHeight(); y += 2)
    for (int x = 0; x < grey.getWidth(); x += 2)
      if (grey.at<uint8_t>(x, y) != first) return false;
  return true;
}

void save_scene(const mrpt::opengl::COpenGLScene& scene, const std::string& path) {
  omnisfm::io::write_atomically(path, [&](const std::string& temporary) {
    if (!scene.saveToFile(temporary)) throw std::runtime_error(path + ": cannot be written");
  });
}

// The command line's choices.
struct SlamOptions {
  std::string rawlog, out, config, screenshot;
  int scene_every = 50;
  bool live = false;
};

// The robot's pose at each camera frame, and the frame's time.
struct RobotPath {
  std::vector<mrpt::poses::CPose3D> poses;
  std::vector<double> times;
};

void show(mrpt::gui::CDisplayWindow3D& window, const mrpt::opengl::COpenGLScene::Ptr& scene) {
  window.get3DSceneAndLock() = scene;
  window.unlockAccess3DScene();
  window.forceRepaint();
}

// The rawlog fed to the estimator through MRPT's map-builder interface, entry by entry; every
// scene_every camera frames the scene saved, and shown live in `window` when there is one.
RobotPath replay(const SlamOptions& o, omnisfm::mrpt_plugin::OmniSfmEstimator* estimator,
                 mrpt::gui::CDisplayWindow3D* window) {
  mrpt::slam::CMetricMapBuilder* builder = estimator;
  // External images (rawlog-edit --externalize) are in a folder beside the rawlog.
  omnisfm::mrpt_plugin::use_external_images_of(o.rawlog);
  mrpt::io::CFileGZInputStream file(o.rawlog);
  auto archive = mrpt::serialization::archiveFrom(file);
  mrpt::obs::CActionCollection::Ptr actions;
  mrpt::obs::CSensoryFrame::Ptr frame;
  mrpt::obs::CObservation::Ptr observation;
  size_t entry = 0;
  RobotPath path;
  for (;;) {
    bool more = false;
    try {
      more = mrpt::obs::CRawlog::getActionObservationPairOrObservation(archive, actions, frame,
                                                                      observation, entry);
    } catch (const std::exception& e) {
      std::cerr << "omnisfm-slam: warning: " << o.rawlog << ": stopped at entry " << entry
                << ", which cannot be read\n";
      break;
    }
    if (!more) break;
    const int frames = estimator->framesProcessed();
    if (observation)
      estimator->processObservation(observation);
    else if (actions && frame)
      builder->processActionObservation(*actions, *frame);
    if (estimator->framesProcessed() == frames) continue;

    path.poses.push_back(builder->getCurrentPoseEstimation()->getMeanVal());
    path.times.push_back(estimator->lastFrameTime());
    const size_t n = path.poses.size();
    const bool save = o.scene_every > 0 && n % static_cast<size_t>(o.scene_every) == 0;
    if (!save && !window) continue;
    const auto scene = scene_of(path.poses, *estimator);
    if (save) {
      std::ostringstream name;
      name << o.out << "/omnisfm_slam_" << std::setw(5) << std::setfill('0') << n << ".3Dscene";
      save_scene(*scene, name.str());
    }
    if (window) show(*window, scene);
  }
  // A sequence shorter than the smoothed start gets it over the frames it had; either way the
  // path takes the first frames as it revised them.
  estimator->finishStart();
  for (const auto& [revised, pose] : estimator->smoothedStartPoses())
    if (revised >= 0 && static_cast<size_t>(revised) < path.poses.size())
      path.poses[revised] = pose;
  return path;
}

void write_tum(const std::string& file, const RobotPath& path) {
  omnisfm::io::write_text_atomically(file, [&](std::ostream& tum) {
    tum << "# timestamp tx ty tz qx qy qz qw (the robot in the map frame)\n"
        << std::setprecision(17);
    for (size_t i = 0; i < path.poses.size(); ++i) {
      const mrpt::poses::CPose3D& p = path.poses[i];
      mrpt::math::CQuaternionDouble q;
      p.getAsQuaternion(q);
      tum << path.times[i] << " " << p.x() << " " << p.y() << " " << p.z() << " " << q.x() << " "
          << q.y() << " " << q.z() << " " << q.r() << "\n";
    }
  });
}

// The window renders in its own thread: wait for a frame that shows the scene, then save it.
void save_screenshot(mrpt::gui::CDisplayWindow3D& window, const std::string& file) {
  mrpt::img::CImage image;
  for (int tries = 0; tries < 100; ++tries) {
    window.forceRepaint();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (window.getLastWindowImage(image) && !is_uniform(image)) break;
  }
  if (image.isEmpty() || is_uniform(image) || !image.saveToFile(file))
    throw std::runtime_error(file + ": the window showed nothing to save");
}

void run(const SlamOptions& o) {
  omnisfm::mrpt_plugin::OmniSfmEstimatorOptions options;
  if (!o.config.empty()) {
    if (!std::filesystem::is_regular_file(o.config))
      throw omnisfm::io::InputError(o.config, 0, "cannot be read");
    options.loadFromConfigFile(mrpt::config::CConfigFile(o.config), "run");
  }
  if (!std::filesystem::is_regular_file(o.rawlog))
    throw omnisfm::io::InputError(o.rawlog, 0, "cannot be read");
  std::filesystem::create_directories(o.out);

  auto estimator = std::make_unique<omnisfm::mrpt_plugin::OmniSfmEstimator>(options);
  mrpt::slam::CMetricMapBuilder* builder = estimator.get();
  builder->initialize();

  mrpt::gui::CDisplayWindow3D::Ptr window;
  if (o.live) {
    if (!std::getenv("DISPLAY"))
      throw std::runtime_error("--live needs a display (DISPLAY is not set)");
    window = mrpt::gui::CDisplayWindow3D::Create("omnisfm-slam", 800, 600);
    window->setCameraZoom(12);
    if (!o.screenshot.empty()) window->captureImagesStart();
  }
  const RobotPath path = replay(o, estimator.get(), window.get());
  if (path.poses.empty()) throw omnisfm::io::InputError(o.rawlog, 0, "holds no camera frame");

  const auto scene = scene_of(path.poses, *estimator);
  save_scene(*scene, o.out + "/final.3Dscene");
  write_tum(o.out + "/estimated_path.tum", path);
  builder->saveCurrentEstimationToImage(o.out + "/top.png");
  if (window) {
    show(*window, scene);
    if (!o.screenshot.empty()) save_screenshot(*window, o.screenshot);
  }
  const auto pose = std::dynamic_pointer_cast<mrpt::poses::CPose3DPDFGaussian>(
      builder->getCurrentPoseEstimation());
  const mrpt::poses::CPose3D& last = path.poses.back();
  std::cout << "omnisfm-slam: " << path.poses.size() << " camera frames, "
            << builder->getCurrentlyBuiltMapSize() << " keyframes; the robot at " << last.x()
            << " " << last.y() << " " << last.z();
  if (pose) std::cout << " +- " << std::sqrt(pose->cov(0, 0)) << " m (x)";
  std::cout << "; wrote " << o.out << "/final.3Dscene, estimated_path.tum, top.png\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "omnisfm's online estimator in an MRPT SLAM application: a rawlog in, the robot's path "
      "(estimated_path.tum), .3Dscene files and a top view (top.png) out"};
  SlamOptions o;
  app.add_option("rawlog", o.rawlog, "The rawlog (either format; load nothing: this program links "
                                     "the plugin)")
      ->required();
  app.add_option("--out", o.out, "Output folder (made when missing)")->required();
  app.add_option("--config", o.config,
                 "An INI file whose [run] section (and [sfm], the filter's) sets the estimator's "
                 "options, as share/omnisfm/config/omnisfm.ini");
  app.add_option("--scene-every", o.scene_every,
                 "Save omnisfm_slam_NNNNN.3Dscene every this many camera frames (0: only "
                 "final.3Dscene)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--live", o.live,
               "Show the scene in a CDisplayWindow3D as it grows (needs a display)");
  app.add_option("--screenshot", o.screenshot,
                 "With --live: save the window's last image as this PNG file");
  CLI11_PARSE(app, argc, argv);
  // The process's settings are the application's: Ceres' warnings off (the estimator reports what
  // it did), and OpenBLAS on one thread for the filter's small matrices.
  FLAGS_minloglevel = google::GLOG_ERROR;
  omnisfm::sfm::use_one_blas_thread();

  try {
    run(o);
    return 0;
  } catch (const omnisfm::io::InputError& e) {
    std::cerr << "omnisfm-slam: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "omnisfm-slam: " << e.what() << "\n";
    return 1;
  }
}
