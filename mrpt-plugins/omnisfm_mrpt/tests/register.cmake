# The plugin's tests: its classes through MRPT serialization, rawlog reading (and damage) and
# writing, the committed rawlog of version 0; then stock MRPT's rawlog-edit loading the plugin on
# a rawlog that `omnisfm simulate --rawlog` wrote.

omnisfm_add_test(omnisfm_mrpt_tests ONE_PROCESS_PER_SUITE
  SOURCES
    tests/camera_model_test.cpp
    tests/observations_test.cpp
    tests/rawlog_reader_test.cpp
    tests/stored_length_test.cpp
    tests/rawlog_input_test.cpp
    tests/simulated_rawlog_test.cpp
    tests/legacy_rawlog_test.cpp
    tests/replay_input_test.cpp
    tests/scene_file_test.cpp
    tests/omni_sfm_estimator_test.cpp
    tests/pose_graph_file_test.cpp
    tests/slam_rawlog_test.cpp
    tests/estimator_options_test.cpp
    tests/motion_sensor_collector_test.cpp
  DEPS omnisfm::mrpt_plugin omnisfm::sim omnisfm::io omnisfm::sfm mrpt::obs mrpt::img mrpt::io
       mrpt::poses mrpt::serialization mrpt::opengl mrpt::graphs mrpt::slam mrpt::maps
       opencv_imgcodecs
  LABELS unit sanitize
  NOT_SANITIZED "OmniSfmEstimator.(IsAnMrptMapBuilder|KeepsNoSensorHistory)"
                "OmniSfmEstimator.(GivesTheSmoothedStartsPoses|PoseIsTheFiltersInTheRobotFrame)"
                SlamRawlog.IsReadByMrptAsActionsAndObservationPairs
                PoseGraphFile.MrptReadsTheBatchsPosesAndEdges)
# The camera contract's cameras: every inner camera and mirror the model must store.
target_include_directories(omnisfm_mrpt_tests PRIVATE ${PROJECT_SOURCE_DIR}/libs/camera/tests
                           ${CMAKE_CURRENT_SOURCE_DIR}/src)
# The pose graph's consistency over seeds (five batches) and whole rover runs with sensor glitches:
# too slow for the sanitizers' build.
omnisfm_add_test(omnisfm_mrpt_consistency_tests
  SOURCES tests/pose_graph_consistency_test.cpp tests/slam_rawlog_consistency_test.cpp
          tests/omni_sfm_batch_estimator_test.cpp tests/sensor_glitch_replay_test.cpp
  DEPS omnisfm::mrpt_plugin omnisfm::sim omnisfm::sfm omnisfm::eval mrpt::poses mrpt::obs mrpt::maps
       mrpt::serialization mrpt::slam LABELS unit)
target_include_directories(omnisfm_mrpt_consistency_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)

target_compile_definitions(omnisfm_mrpt_tests PRIVATE
  OMNISFM_MRPT_TEST_DATA="${CMAKE_CURRENT_SOURCE_DIR}/tests/data")

# The reference rawlog of the classes' current versions, for a class's next version to commit as
# tests/data/versionN.rawlog (legacy_rawlog_objects.h); a tool, not a test.
add_executable(write_legacy_rawlog tests/write_legacy_rawlog.cpp)
target_link_libraries(write_legacy_rawlog PRIVATE omnisfm::mrpt_plugin omnisfm::sim mrpt::obs
                      mrpt::io mrpt::serialization GTest::gtest)
target_include_directories(write_legacy_rawlog PRIVATE ${PROJECT_SOURCE_DIR}/libs/camera/tests)
omnisfm_warnings(write_legacy_rawlog)

# A stock MRPT app the tests run (Debian: mrpt-apps), found as VARIABLE.
function(omnisfm_find_mrpt_app variable app)
  find_program(${variable} ${app})
  if(NOT ${variable})
    message(WARNING "${app} not found (Debian: mrpt-apps); the tests that run it will fail")
    set(${variable} ${app} PARENT_SCOPE)
  endif()
endfunction()
omnisfm_find_mrpt_app(OMNISFM_RAWLOG_EDIT rawlog-edit)

set(lab_dir ${CMAKE_CURRENT_BINARY_DIR}/rawlog_lab)
set(lab_rawlog ${lab_dir}/dataset.rawlog)
# Stock tools load the classes' library; the whole plugin, which links it, serves as well.
set(plugin $<TARGET_FILE:omnisfm_mrpt_classes>)
set(full_plugin $<TARGET_FILE:omnisfm_mrpt>)
set(check ${CMAKE_CURRENT_SOURCE_DIR}/tests/check_output.cmake)

add_test(NAME omnisfm_simulate_rawlog
  COMMAND omnisfm simulate --scenario lab --out ${lab_dir} --rawlog --render
          --width 256 --height 192 --samples 1)
set_tests_properties(omnisfm_simulate_rawlog PROPERTIES
  LABELS interop FIXTURES_SETUP mrpt_lab_rawlog
  PASS_REGULAR_EXPRESSION "dataset.rawlog with 41 images, 41 tracked frames, 401 odometry, 4001 gyro readings")

# --info parses every object: 1 comment, the camera model and 41 stock images (OMNI_CAMERA), 41
# tracked frames, 401 odometry, 4001 gyro.
add_test(NAME rawlog_edit_info
  COMMAND ${CMAKE_COMMAND}
          "-DCOMMAND=${OMNISFM_RAWLOG_EDIT}|-p|${plugin}|--info|-i|${lab_rawlog}"
          "-DEXPECTED=Overall number of objects         : 4486|OMNI_CAMERA /     42 /|OMNI_TRACKS /     41 /1.000|ODOMETRY /    401 /10.000|IMU /   4001 /100.000"
          "-DUNEXPECTED=exception"
          -P ${check})
# --describe prints each object's getDescriptionAsText.
add_test(NAME rawlog_edit_describe
  COMMAND ${CMAKE_COMMAND}
          "-DCOMMAND=${OMNISFM_RAWLOG_EDIT}|-p|${full_plugin}|--describe|-i|${lab_rawlog}"
          "-DEXPECTED=ClassName: omnisfm::mrpt_plugin::CObservationCameraModel|ClassName: mrpt::obs::CObservationImage|ClassName: omnisfm::mrpt_plugin::CObservationTrackedFeatures|Catadioptric camera model: pinhole camera, equiangular mirror, 256x192 pixels|Tracked features (omnisfm): frame 40, 44 features|ClassName: mrpt::obs::CObservationOdometry|ClassName: mrpt::obs::CObservationIMU"
          "-DUNEXPECTED=exception"
          -P ${check})
# Without the plugin rawlog-edit stops at the camera model and names its class; the rawlog's
# leading comment, which --describe prints, says to load libomnisfm_mrpt_classes.so.
add_test(NAME rawlog_edit_without_plugin
  COMMAND ${CMAKE_COMMAND}
          "-DCOMMAND=${OMNISFM_RAWLOG_EDIT}|--describe|-i|${lab_rawlog}"
          "-DEXPECTED=rawlog-edit -p /path/to/libomnisfm_mrpt_classes.so|Stored object has class 'omnisfm::mrpt_plugin::CObservationCameraModel' which is not registered"
          -P ${check})
# --export-txt writes the tracked features' table, which must hold exactly the simulated tracks.
find_package(Python3 REQUIRED COMPONENTS Interpreter)
add_test(NAME rawlog_edit_export_txt
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/tests/export_txt_matches_tracks.py
          ${OMNISFM_RAWLOG_EDIT} ${plugin} ${lab_rawlog} ${lab_dir}/tracks.vnl)
set_tests_properties(rawlog_edit_info rawlog_edit_describe rawlog_edit_without_plugin
                     rawlog_edit_export_txt PROPERTIES
  LABELS interop FIXTURES_REQUIRED mrpt_lab_rawlog TIMEOUT 120)
# The classes' library needs MRPT's obs and nothing of the estimators, replay or geodesy.
add_test(NAME plugin_classes_library_needs_only_obs
  COMMAND ${CMAKE_COMMAND} "-DCOMMAND=readelf|-d|${plugin}"
          "-DEXPECTED=Shared library: [libmrpt-obs.so"
          "-DUNEXPECTED=[libomnisfm_mrpt.so|[libmrpt-slam.so|[libmrpt-maps.so|[libmrpt-graphs.so|[libmrpt-gui.so|[libGeographic|[libceres.so|[libopencv_imgproc.so|[libopencv_video.so"
          -P ${check})
set_tests_properties(plugin_classes_library_needs_only_obs PROPERTIES LABELS unit)

# Stock graph-slam on the batch's pose graph (batch.graph, written by sfm beside batch.tum).
omnisfm_find_mrpt_app(OMNISFM_GRAPH_SLAM graph-slam)
set(rover_sim ${CMAKE_CURRENT_BINARY_DIR}/graph_rover_sim)
set(rover_sfm ${CMAKE_CURRENT_BINARY_DIR}/graph_rover_sfm)
add_test(NAME omnisfm_simulate_rover_for_graph
  COMMAND omnisfm simulate --scenario rover --out ${rover_sim})
add_test(NAME omnisfm_sfm_rover_graph
  COMMAND omnisfm sfm --camera ${rover_sim}/camera.ini --tracks ${rover_sim}/tracks.vnl
          --out ${rover_sfm})
set_tests_properties(omnisfm_simulate_rover_for_graph PROPERTIES
  LABELS interop FIXTURES_SETUP rover_for_graph TIMEOUT 300)
set_tests_properties(omnisfm_sfm_rover_graph PROPERTIES
  LABELS interop FIXTURES_REQUIRED rover_for_graph FIXTURES_SETUP rover_batch_graph TIMEOUT 300)
add_test(NAME graph_slam_reads_batch_graph
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/tests/graph_slam_reads_batch_graph.py
          ${OMNISFM_GRAPH_SLAM} ${rover_sfm}/batch.graph)
set_tests_properties(graph_slam_reads_batch_graph PROPERTIES
  LABELS interop FIXTURES_REQUIRED rover_batch_graph TIMEOUT 120)

# Stock kf-slam on the rawlog of stock classes that `omnisfm run --slam-rawlog` writes for the
# simulated rover (odometry, gyro and vision fused): its path within 2 % of the distance of the
# truth after a rigid alignment. rawlog-edit reads that rawlog without the plugin.
omnisfm_find_mrpt_app(OMNISFM_KF_SLAM kf-slam)
set(kf_rover ${CMAKE_CURRENT_BINARY_DIR}/kf_slam_rover)
add_test(NAME omnisfm_simulate_rover_for_kf_slam
  COMMAND omnisfm simulate --scenario rover --out ${kf_rover}_sim --rawlog)
set_tests_properties(omnisfm_simulate_rover_for_kf_slam PROPERTIES
  LABELS interop FIXTURES_SETUP rover_for_kf_slam TIMEOUT 300)
add_test(NAME omnisfm_run_slam_rawlog
  COMMAND omnisfm run ${kf_rover}_sim/dataset.rawlog --out ${kf_rover}_run
          --slam-rawlog ${kf_rover}_sim/slam.rawlog)
set_tests_properties(omnisfm_run_slam_rawlog PROPERTIES
  LABELS interop FIXTURES_REQUIRED rover_for_kf_slam FIXTURES_SETUP rover_slam_rawlog TIMEOUT 300
  PASS_REGULAR_EXPRESSION "slam rawlog [^\n]*: 150 frames, [0-9]+ landmark measurements")
add_test(NAME rawlog_edit_info_slam_rawlog
  COMMAND ${CMAKE_COMMAND}
          "-DCOMMAND=${OMNISFM_RAWLOG_EDIT}|--info|-i|${kf_rover}_sim/slam.rawlog"
          "-DEXPECTED=Overall number of objects         : 300|Actions/SensoryFrame format       : Yes|OMNI_LANDMARKS /    150"
          "-DUNEXPECTED=exception"
          -P ${check})
add_executable(kf_slam_follows_truth tests/kf_slam_follows_truth.cpp)
target_link_libraries(kf_slam_follows_truth PRIVATE omnisfm::eval omnisfm::io mrpt::obs mrpt::io
                      mrpt::poses mrpt::serialization)
target_include_directories(kf_slam_follows_truth PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
omnisfm_warnings(kf_slam_follows_truth)
add_test(NAME kf_slam_follows_truth
  COMMAND kf_slam_follows_truth ${OMNISFM_KF_SLAM}
          ${PROJECT_SOURCE_DIR}/share/omnisfm/config/kf-slam-6d.ini ${kf_rover}_sim/slam.rawlog
          ${kf_rover}_sim/ground_truth.tum ${kf_rover}_sim 2)
set_tests_properties(rawlog_edit_info_slam_rawlog kf_slam_follows_truth PROPERTIES
  LABELS interop FIXTURES_REQUIRED rover_slam_rawlog TIMEOUT 300)
# The same on the lab, whose camera hangs upside down on the robot: the increments are the robot's,
# and kf-slam puts the camera back at sensorLocationOnRobot.
add_test(NAME omnisfm_run_lab_slam_rawlog
  COMMAND omnisfm run ${lab_rawlog} --out ${lab_dir}_run --slam-rawlog ${lab_dir}/slam.rawlog)
set_tests_properties(omnisfm_run_lab_slam_rawlog PROPERTIES
  LABELS interop FIXTURES_REQUIRED mrpt_lab_rawlog FIXTURES_SETUP lab_slam_rawlog TIMEOUT 300
  PASS_REGULAR_EXPRESSION "slam rawlog [^\n]*: 41 frames, [0-9]+ landmark measurements")
add_test(NAME kf_slam_follows_truth_lab
  COMMAND kf_slam_follows_truth ${OMNISFM_KF_SLAM}
          ${PROJECT_SOURCE_DIR}/share/omnisfm/config/kf-slam-6d.ini ${lab_dir}/slam.rawlog
          ${lab_dir}/ground_truth.tum ${lab_dir} 2)
set_tests_properties(kf_slam_follows_truth_lab PROPERTIES
  LABELS interop FIXTURES_REQUIRED lab_slam_rawlog TIMEOUT 300)

# Stock rawlog-edit --externalize stores every rendered lab image as a file (they are stock
# CObservationImage), --list-images lists them, and omnisfm tracks them as it tracks the original.
add_test(NAME rawlog_edit_externalize
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/tests/externalize_keeps_images.py
          ${OMNISFM_RAWLOG_EDIT} ${plugin} ${lab_rawlog} $<TARGET_FILE:omnisfm> 41
          $<TARGET_FILE:omnisfm-slam>)
set_tests_properties(rawlog_edit_externalize PROPERTIES
  LABELS interop FIXTURES_REQUIRED mrpt_lab_rawlog TIMEOUT 120)

# omnisfm-slam, the example MRPT application, on the rendered lab's rawlog (its images and their
# tracks: the first kind to arrive, the images, is the vision, each frame once): its scenes, path
# and top view; then with its live window, under a virtual display (Debian: xvfb).
set(slam_app_out ${CMAKE_CURRENT_BINARY_DIR}/omnisfm_slam_lab)
add_test(NAME omnisfm_slam_app
  COMMAND ${CMAKE_COMMAND}
          "-DCOMMAND=$<TARGET_FILE:omnisfm-slam>|${lab_rawlog}|--out|${slam_app_out}|--scene-every|20"
          "-DEXPECTED=omnisfm-slam: 41 camera frames|wrote ${slam_app_out}/final.3Dscene"
          "-DUNEXPECTED=warning"
          -P ${check})
add_test(NAME omnisfm_slam_app_outputs
  COMMAND ${Python3_EXECUTABLE} -c
          "import pathlib, sys; d = pathlib.Path(sys.argv[1]); rows = [l for l in (d / 'estimated_path.tum').read_text().splitlines() if not l.startswith('#')]; assert len(rows) == 41, len(rows); assert all(len(r.split()) == 8 for r in rows); assert all((d / f).stat().st_size > 1000 for f in ('final.3Dscene', 'omnisfm_slam_00020.3Dscene', 'omnisfm_slam_00040.3Dscene', 'top.png')); assert (d / 'top.png').read_bytes().startswith(bytes([137, 80, 78, 71]))"
          ${slam_app_out})
set_tests_properties(omnisfm_slam_app PROPERTIES
  LABELS interop FIXTURES_REQUIRED mrpt_lab_rawlog FIXTURES_SETUP slam_app_lab TIMEOUT 300)
set_tests_properties(omnisfm_slam_app_outputs PROPERTIES
  LABELS interop FIXTURES_REQUIRED slam_app_lab TIMEOUT 60)
find_program(OMNISFM_XVFB_RUN xvfb-run)
if(NOT OMNISFM_XVFB_RUN)
  message(WARNING "xvfb-run not found (Debian: xvfb); the live-window test will fail")
  set(OMNISFM_XVFB_RUN xvfb-run)
endif()
# The window's screenshot must show something (the program refuses a uniform image). Mesa's
# llvmpipe renders MRPT's windows black under Xvfb on the test machine; softpipe draws them.
add_test(NAME omnisfm_slam_app_live
  COMMAND ${OMNISFM_XVFB_RUN} -a $<TARGET_FILE:omnisfm-slam> ${lab_rawlog}
          --out ${slam_app_out}_live --scene-every 0 --live
          --screenshot ${slam_app_out}_live/window.png)
set_tests_properties(omnisfm_slam_app_live PROPERTIES
  LABELS interop FIXTURES_REQUIRED mrpt_lab_rawlog TIMEOUT 300 ENVIRONMENT GALLIUM_DRIVER=softpipe
  PASS_REGULAR_EXPRESSION "omnisfm-slam: 41 camera frames")
