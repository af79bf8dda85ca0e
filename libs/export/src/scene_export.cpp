#include "dlo/export/scene_export.h"

#include <mrpt/img/CImage.h>
#include <mrpt/img/color_maps.h>
#include <mrpt/opengl/CFBORender.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/stock_objects.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "dlo/export/height_range.h"
#include "dlo/files/atomic_file.h"
#include "dlo/formats/png_file.h"
#include "dlo/mrpt/pose_conversion.h"

namespace dlo {

namespace {

mrpt::opengl::CSetOfLines::Ptr lines(float r, float g, float b, float width) {
  auto l = mrpt::opengl::CSetOfLines::Create();
  l->setColor(r, g, b);
  l->setLineWidth(width);
  return l;
}

void appendSegment(mrpt::opengl::CSetOfLines& l, const Eigen::Vector3d& a,
                   const Eigen::Vector3d& b) {
  l.appendLine(a.x(), a.y(), a.z(), b.x(), b.y(), b.z());
}

}  // namespace

mrpt::opengl::COpenGLScene::Ptr buildMapScene(const SlamMap& map, const WeightedCloud& world_points,
                                              const SceneOptions& options) {
  auto scene = mrpt::opengl::COpenGLScene::Create();

  auto cloud = mrpt::opengl::CPointCloudColoured::Create();
  cloud->setPointSize(options.point_size);
  std::vector<float> heights;
  heights.reserve(world_points.size());
  for (const WeightedPoint& wp : world_points) heights.push_back(wp.p.z());
  const auto range = colourHeightRange(std::move(heights), 2.0, 98.0);
  const float lo = static_cast<float>(range.first), hi = static_cast<float>(range.second);
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(1e30), upper = -lower;
  for (const WeightedPoint& wp : world_points) {
    float r, g, b;
    mrpt::img::colormap(mrpt::img::cmJET, std::clamp((wp.p.z() - lo) / (hi - lo), 0.0f, 1.0f), r, g,
                        b);
    cloud->push_back(wp.p.x(), wp.p.y(), wp.p.z(), r, g, b);
    lower = lower.cwiseMin(wp.p.cast<double>());
    upper = upper.cwiseMax(wp.p.cast<double>());
  }
  scene->insert(cloud);

  auto path = lines(0.1f, 0.1f, 0.1f, 3.0f);
  path->setName("trajectory");
  for (size_t i = 1; i < map.frames.size(); ++i) {
    appendSegment(*path, map.framePose(i - 1).translation(), map.framePose(i).translation());
  }
  scene->insert(path);

  auto loops = lines(1.0f, 0.0f, 1.0f, 3.0f);
  loops->setName("loop_closures");
  const int n = static_cast<int>(map.keyframes.size());
  for (const PoseEdge& e : map.edges) {
    if (!e.loop || e.from < 0 || e.to < 0 || e.from >= n || e.to >= n) continue;
    appendSegment(*loops, map.keyframes[e.from].pose.translation(),
                  map.keyframes[e.to].pose.translation());
  }
  scene->insert(loops);

  for (const Keyframe& kf : map.keyframes) {
    lower = lower.cwiseMin(kf.pose.translation());
    upper = upper.cwiseMax(kf.pose.translation());
  }
  if (lower.x() > upper.x()) lower = upper = Eigen::Vector3d::Zero();
  const Eigen::Vector3d centre = 0.5 * (lower + upper);
  const double extent = std::max((upper - lower).head<2>().norm(), 1.0);

  const float corner_size =
      options.corner_size > 0 ? options.corner_size : static_cast<float>(0.03 * extent);
  for (const Keyframe& kf : map.keyframes) {
    auto corner = mrpt::opengl::stock_objects::CornerXYZSimple(corner_size, 2.0f);
    corner->setPose(toCPose3D(kf.pose));
    scene->insert(corner);
  }

  auto viewport = scene->getViewport("main");
  // Light grey: the jet colormap's dark blue (the ground) would vanish on black.
  viewport->setCustomBackgroundColor(mrpt::img::TColorf(0.85f, 0.85f, 0.85f));
  mrpt::opengl::CCamera& camera = viewport->getCamera();
  camera.setPointingAt(static_cast<float>(centre.x()), static_cast<float>(centre.y()),
                       static_cast<float>(centre.z()));
  // The default 30 deg vertical field of view spans about 0.54 x distance; seen at an angle the
  // map's depth is foreshortened, so ~0.9 diagonals fill the 4:3 image.
  camera.setZoomDistance(static_cast<float>(options.camera_distance * extent));
  camera.setAzimuthDegrees(static_cast<float>(options.azimuth_deg));
  camera.setElevationDegrees(static_cast<float>(options.elevation_deg));
  return scene;
}

void exportScene(const mrpt::opengl::COpenGLScene& scene, const std::string& path) {
  writeAtomically(path, [&](const std::string& temp) {
    if (!scene.saveToFile(temp)) throw std::runtime_error("COpenGLScene::saveToFile failed");
  });
}

void renderScenePng(const mrpt::opengl::COpenGLScene& scene, const std::string& path,
                    const SceneOptions& options) {
  mrpt::img::CImage rgb;
  try {
    mrpt::opengl::CFBORender render(static_cast<unsigned>(options.render_width),
                                    static_cast<unsigned>(options.render_height));
    const auto viewport = scene.getViewport("main");
    render.setCamera(scene, viewport->getCamera());
    render.render_RGB(scene, rgb);
  } catch (const std::exception& e) {
    const std::string what = e.what();
    throw OutputError("cannot render '" + path + "' (no off-screen OpenGL through EGL: " +
                      what.substr(0, what.find('\n')) + ").");
  }
  writePng(rgb.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY), path);
}

}  // namespace dlo
