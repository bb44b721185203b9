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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "omnisfm's online estimator in an MRPT SLAM application: a rawlog in, the robot's path "
      "(estimated_path.tum), .3Dscene files and a top view (top.png) out"};
  std::string rawlog, out, config, screenshot;
  int scene_every = 50;
  bool live = false;
  app.add_option("rawlog", rawlog, "The rawlog (either format; load nothing: this program links "
                                   "the plugin)")
      ->required();
  app.add_option("--out", out, "Output folder (made when missing)")->required();
  app.add_option("--config", config,
                 "An INI file whose [run] section (and [sfm], the filter's) sets the estimator's "
                 "options, as share/omnisfm/config/omnisfm.ini");
  app.add_option("--scene-every", scene_every,
                 "Save omnisfm_slam_NNNNN.3Dscene every this many camera frames (0: only "
                 "final.3Dscene)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--live", live, "Show the scene in a CDisplayWindow3D as it grows (needs a display)");
  app.add_option("--screenshot", screenshot,
                 "With --live: save the window's last image as this PNG file");
  CLI11_PARSE(app, argc, argv);
  // The process's settings are the application's: Ceres' warnings off (the estimator reports what
  // it did), and OpenBLAS on one thread for the filter's small matrices.
  FLAGS_minloglevel = google::GLOG_ERROR;
  omnisfm::sfm::use_one_blas_thread();

  try {
    omnisfm::mrpt_plugin::OmniSfmEstimatorOptions options;
    if (!config.empty()) {
      if (!std::filesystem::is_regular_file(config))
        throw omnisfm::io::InputError(config, 0, "cannot be read");
      options.loadFromConfigFile(mrpt::config::CConfigFile(config), "run");
    }
    if (!std::filesystem::is_regular_file(rawlog))
      throw omnisfm::io::InputError(rawlog, 0, "cannot be read");
    std::filesystem::create_directories(out);

    auto estimator = std::make_unique<omnisfm::mrpt_plugin::OmniSfmEstimator>(options);
    mrpt::slam::CMetricMapBuilder* builder = estimator.get();
    builder->initialize();

    mrpt::gui::CDisplayWindow3D::Ptr window;
    if (live) {
      if (!std::getenv("DISPLAY"))
        throw std::runtime_error("--live needs a display (DISPLAY is not set)");
      window = mrpt::gui::CDisplayWindow3D::Create("omnisfm-slam", 800, 600);
      window->setCameraZoom(12);
      if (!screenshot.empty()) window->captureImagesStart();
    }

    // External images (rawlog-edit --externalize) are in a folder beside the rawlog.
    omnisfm::mrpt_plugin::use_external_images_of(rawlog);
    mrpt::io::CFileGZInputStream file(rawlog);
    auto archive = mrpt::serialization::archiveFrom(file);
    mrpt::obs::CActionCollection::Ptr actions;
    mrpt::obs::CSensoryFrame::Ptr frame;
    mrpt::obs::CObservation::Ptr observation;
    size_t entry = 0;
    std::vector<mrpt::poses::CPose3D> path;
    std::vector<double> times;
    for (;;) {
      bool more = false;
      try {
        more = mrpt::obs::CRawlog::getActionObservationPairOrObservation(archive, actions, frame,
                                                                        observation, entry);
      } catch (const std::exception& e) {
        std::cerr << "omnisfm-slam: warning: " << rawlog << ": stopped at entry " << entry
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

      const auto pose = builder->getCurrentPoseEstimation();
      path.push_back(pose->getMeanVal());
      times.push_back(estimator->lastFrameTime());
      const bool save = scene_every > 0 && path.size() % static_cast<size_t>(scene_every) == 0;
      if (!save && !window) continue;
      const auto scene = scene_of(path, *estimator);
      if (save) {
        std::ostringstream name;
        name << out << "/omnisfm_slam_" << std::setw(5) << std::setfill('0') << path.size()
             << ".3Dscene";
        save_scene(*scene, name.str());
      }
      if (window) {
        mrpt::opengl::COpenGLScene::Ptr& shown = window->get3DSceneAndLock();
        shown = scene;
        window->unlockAccess3DScene();
        window->forceRepaint();
      }
    }
    if (path.empty()) throw omnisfm::io::InputError(rawlog, 0, "holds no camera frame");

    const auto scene = scene_of(path, *estimator);
    save_scene(*scene, out + "/final.3Dscene");
    omnisfm::io::write_text_atomically(out + "/estimated_path.tum", [&](std::ostream& tum) {
      tum << "# timestamp tx ty tz qx qy qz qw (the robot in the map frame)\n"
          << std::setprecision(17);
      for (size_t i = 0; i < path.size(); ++i) {
        mrpt::math::CQuaternionDouble q;
        path[i].getAsQuaternion(q);
        tum << times[i] << " " << path[i].x() << " " << path[i].y() << " " << path[i].z() << " "
            << q.x() << " " << q.y() << " " << q.z() << " " << q.r() << "\n";
      }
    });
    builder->saveCurrentEstimationToImage(out + "/top.png");
    if (window) {
      window->get3DSceneAndLock() = scene;
      window->unlockAccess3DScene();
      window->forceRepaint();
      if (!screenshot.empty()) {
        // The window renders in its own thread: wait for a frame that shows the scene.
        mrpt::img::CImage image;
        for (int tries = 0; tries < 100; ++tries) {
          window->forceRepaint();
          std::this_thread::sleep_for(std::chrono::milliseconds(100));
          if (window->getLastWindowImage(image) && !is_uniform(image)) break;
        }
        if (image.isEmpty() || is_uniform(image) || !image.saveToFile(screenshot))
          throw std::runtime_error(screenshot + ": the window showed nothing to save");
      }
    }
    const auto pose = std::dynamic_pointer_cast<mrpt::poses::CPose3DPDFGaussian>(
        builder->getCurrentPoseEstimation());
    std::cout << "omnisfm-slam: " << path.size() << " camera frames, "
              << builder->getCurrentlyBuiltMapSize() << " keyframes; the robot at "
              << path.back().x() << " " << path.back().y() << " " << path.back().z();
    if (pose) std::cout << " +- " << std::sqrt(pose->cov(0, 0)) << " m (x)";
    std::cout << "; wrote " << out << "/final.3Dscene, estimated_path.tum, top.png\n";
    return 0;
  } catch (const omnisfm::io::InputError& e) {
    std::cerr << "omnisfm-slam: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "omnisfm-slam: " << e.what() << "\n";
    return 1;
  }
}
