/// \file scene_export.h
/// \brief The map as an MRPT 3D scene (`map.3Dscene`) and its off-screen rendering (PNG).
#pragma once

#include <mrpt/opengl/COpenGLScene.h>
#include <string>

#include "dlo/core/weighted_cloud.h"
#include "dlo/slam/slam_map.h"

namespace dlo {

/// How the 3D scene is built and rendered.
struct SceneOptions {
  float point_size = 2.0f;       ///< pixels
  float corner_size = 0.0f;      ///< metres, keyframe axes; 0: 3 % of the map's diagonal
  int render_width = 1280;       ///< pixels
  int render_height = 960;       ///< pixels
  double elevation_deg = 50;     ///< camera elevation above the ground plane
  double azimuth_deg = -60;      ///< camera azimuth around +z
  double camera_distance = 0.9;  ///< camera distance in map diagonals (of points and poses)
};

/// A scene with `world_points` (CPointCloudColoured, coloured by height with the jet colormap
/// over the 2nd-98th percentile), the frame trajectory (dark grey CSetOfLines), accepted loop
/// closures (magenta CSetOfLines) and an XYZ corner at every keyframe pose. The main viewport's
/// camera looks at the middle of the map from above at an angle, far enough to see all of it.
mrpt::opengl::COpenGLScene::Ptr buildMapScene(const SlamMap& map, const WeightedCloud& world_points,
                                              const SceneOptions& options = SceneOptions());

/// Saves `scene` with COpenGLScene::saveToFile (gz-compressed), atomically.
/// \throws OutputError naming `path`.
void exportScene(const mrpt::opengl::COpenGLScene& scene, const std::string& path);

/// Renders `scene` from its main viewport's camera off-screen with mrpt::opengl::CFBORender
/// (EGL: works without a display) and writes a PNG, atomically.
/// \throws OutputError naming `path` if no EGL/OpenGL context can be created or rendering fails;
///         callers can treat it as a warning.
void renderScenePng(const mrpt::opengl::COpenGLScene& scene, const std::string& path,
                    const SceneOptions& options = SceneOptions());

}  // namespace dlo
