#pragma once
// The scene write_scene_file saves (scene_file.h states its objects), as an MRPT object: for a
// program that shows it (a CDisplayWindow3D) as well as saving it.
//
// MRPT headers: the including target must link MRPT (mrpt::opengl) itself.

#include <mrpt/opengl/COpenGLScene.h>

#include "omnisfm/mrpt_plugin/scene_file.h"

namespace omnisfm::mrpt_plugin {

mrpt::opengl::COpenGLScene::Ptr make_scene(const SceneContents& contents);

}  // namespace omnisfm::mrpt_plugin
