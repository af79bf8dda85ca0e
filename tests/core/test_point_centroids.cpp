// Cells at the centroids of their points (SelectionParams::centroid_levels): a spinning
// sensor's rings sample a kerb's edge at places that move with the sensor, and a cell's mean
// height compared at the cell's centre then biases registrations by a pattern that moves with
// the sensor.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dlo/core/deskew.h"
#include "dlo/core/direct_aligner.h"
#include "dlo/core/dlo_params.h"
#include "dlo/core/height_frame.h"
#include "dlo/core/rigid_transform.h"
#include "dlo/core/units.h"

namespace dlo {
namespace {

constexpr double kSensorHeight = 1.8;
constexpr double kKerbY = 3.0;  // kerbs at y = +-3 m
constexpr double kKerbHeight = 0.13;

/// A sweep of a straight road with a kerb on either side, from a sensor at (x0, 0, 1.8) m:
/// 64 rings from -2 to -24.8 deg (0.36 deg apart) at 0.2 deg of azimuth, each ray ending on the
/// road, on a kerb's face or on the pavement behind it. Two poles and a box give the position
/// along the road; they are sampled on a grid fixed in the world (not by the rays), so that
/// only the kerbs' sampling moves with the sensor. Points in the sensor frame.
PointCloud roadSweep(double x0, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.005);
  PointCloud pts;
  for (int ring = 0; ring < 64; ++ring) {
    const double el = (-2.0 - 0.36 * ring) * kDeg;
    for (int a = 0; a < 1800; ++a) {
      const double az = 0.2 * a * kDeg;
      const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                              std::sin(el));
      // The pavement behind a kerb (z = 0.13 above the road), else the road, else the face.
      const double t_top = -(kSensorHeight - kKerbHeight) / d.z();
      const double t_road = -kSensorHeight / d.z();
      Eigen::Vector3d p;
      if (std::abs(t_top * d.y()) >= kKerbY) {
        p = t_top * d;
      } else if (std::abs(t_road * d.y()) <= kKerbY) {
        p = t_road * d;
      } else {
        const double t_face = kKerbY / std::abs(d.y());
        p = t_face * d;
      }
      if (p.head<2>().norm() > 19.0) continue;
      p.z() += noise(rng);
      pts.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                       static_cast<float>(p.z()));
    }
  }
  const auto add = [&](double x, double y, double z) {
    pts.emplace_back(static_cast<float>(x - x0), static_cast<float>(y),
                     static_cast<float>(z - kSensorHeight + noise(rng)));
  };
  // Poles (0.2 m square, 3 m high) and boxes (1 m high, tops only) at fixed world places.
  for (const Eigen::Vector2d& pole : {Eigen::Vector2d(7.0, 4.5), Eigen::Vector2d(-9.0, -5.0),
                                      Eigen::Vector2d(-3.0, 6.0), Eigen::Vector2d(15.0, -6.0)}) {
    for (double z = 0.0; z < 3.0; z += 0.05) {
      for (double u = -0.1; u <= 0.1; u += 0.02) {
        add(pole.x() + u, pole.y() - 0.1, z + kKerbHeight);
        add(pole.x() + u, pole.y() + 0.1, z + kKerbHeight);
        add(pole.x() - 0.1, pole.y() + u, z + kKerbHeight);
        add(pole.x() + 0.1, pole.y() + u, z + kKerbHeight);
      }
    }
  }
  for (const Eigen::Vector4d& box :
       {Eigen::Vector4d(12.0, -5.0, 2.0, 1.0), Eigen::Vector4d(-14.0, 4.0, 3.0, 1.5),
        Eigen::Vector4d(2.0, 8.0, 1.5, 2.0), Eigen::Vector4d(-6.0, -9.0, 2.5, 1.0),
        Eigen::Vector4d(9.0, 10.0, 1.0, 3.0), Eigen::Vector4d(-12.0, -12.0, 2.0, 2.0)}) {
    for (double x = box(0); x <= box(0) + box(2); x += 0.02) {
      for (double y = box(1); y <= box(1) + box(3); y += 0.02) add(x, y, 1.0 + kKerbHeight);
    }
  }
  return pts;
}

/// The motion along the road registered from no motion, with cells at their centroids on the
/// finest `centroid_levels` levels (0: at their centres).
double registeredAlongRoad(double moved, int centroid_levels) {
  DloParams params;
  params.selection.centroid_levels = centroid_levels;
  const HeightFrame ref =
      HeightFrame::fromPoints(roadSweep(0.0, 1), params.grid, params.selection, false);
  const HeightFrame cur =
      HeightFrame::fromPoints(roadSweep(moved, 2), params.grid, params.selection, false);
  const AlignmentResult r =
      DirectAligner(params.solver).align(ref, cur, Eigen::Isometry3d::Identity());
  EXPECT_FALSE(r.degenerate);
  return r.pose.translation().x();
}

TEST(PointCentroids, KerbsSampledByRingsDoNotBiasTheRegistration) {
  // The kerbs' cells look the same from every place along the road, but their mean heights
  // depend on where the rings cross them: at the cells' centres they bias the registration by
  // 2.7-4 cm here.
  for (const double moved : {0.15, 0.25, 0.35}) {
    SCOPED_TRACE("moved " + std::to_string(moved));
    const double centres = registeredAlongRoad(moved, 0);
    const double centroids = registeredAlongRoad(moved, 2);
    std::printf("moved %.2f m: registered %.3f m with cell centres, %.3f m with centroids\n", moved,
                centres, centroids);
    EXPECT_LT(std::abs(centroids - moved), 0.02);
    EXPECT_LT(std::abs(centroids - moved), std::abs(centres - moved));
  }
}

TEST(PointCentroids, OffsetsAreTheCentroidsOfTheCellsPoints) {
  // Two points in one 0.1 m cell, both in its lower left quarter: the cell stands at their mean.
  DloParams params;
  params.grid.min_points = 1;
  params.selection.min_gradient = 0.0;
  params.selection.block_size = 1;
  params.selection.centroid_levels = 2;
  const PointCloud points = {{0.02f, 0.01f, 0.0f}, {0.04f, 0.03f, 0.0f}, {0.55f, 0.55f, 1.0f}};
  const HeightFrame f = HeightFrame::fromPoints(points, params.grid, params.selection, false);
  const FrameLevel& level = f.levels()[0];
  const GridGeometry& geo = level.grid.geometry();
  ASSERT_EQ(level.grid_offsets.size(), static_cast<size_t>(geo.cellCount()));
  const int c = static_cast<int>(geo.u(0.03)), r = static_cast<int>(geo.v(0.02));
  const Eigen::Vector2f off = level.grid_offsets[static_cast<size_t>(r * geo.cols + c)];
  // Within 0.01 mm: rasterisation places points in float cell coordinates (u about 200 here,
  // a float step of 1.5e-5 cells).
  EXPECT_NEAR(off.x(), 0.03 - geo.cellCentreX(c), 1e-5);
  EXPECT_NEAR(off.y(), 0.02 - geo.cellCentreY(r), 1e-5);
  // Levels beyond centroid_levels keep their cells at their centres.
  EXPECT_FALSE(f.levels()[1].grid_offsets.empty());
  EXPECT_TRUE(f.levels()[2].grid_offsets.empty());
  // Selected cells carry their offsets too: the same centroid.
  ASSERT_EQ(level.cell_offsets.size(), level.cells.size());
  int found = 0;
  for (size_t i = 0; i < level.cells.size(); ++i) {
    const int ci = static_cast<int>(geo.u(level.cells[i].x));
    const int ri = static_cast<int>(geo.v(level.cells[i].y));
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int n = 0;
    for (const Eigen::Vector3f& p : points) {
      if (static_cast<int>(geo.u(p.x())) != ci || static_cast<int>(geo.v(p.y())) != ri) continue;
      sum += p.head<2>().cast<double>();
      ++n;
    }
    if (n == 0) continue;  // a filled cell next to the points
    ++found;
    EXPECT_NEAR(level.cells[i].x + level.cell_offsets[i].x(), sum.x() / n, 1e-5);
    EXPECT_NEAR(level.cells[i].y + level.cell_offsets[i].y(), sum.y() / n, 1e-5);
  }
  EXPECT_GT(found, 0) << "a cell with points was selected";
  params.selection.centroid_levels = 0;
  const HeightFrame g = HeightFrame::fromPoints(points, params.grid, params.selection, false);
  EXPECT_TRUE(g.levels()[0].grid_offsets.empty());
  EXPECT_TRUE(g.levels()[0].cell_offsets.empty());
}

TEST(PointCentroids, OffsetsAreTheCentroidsOfADeskewedSweep) {
  // The offsets come from where in its cell rasterisation puts each point (moved by the sweep's
  // motion): the same as the centroids of the deskewed points, counted by brute force, on every
  // centroid level, for the reference's cells and the scan's selected cells alike. A point on a
  // cell's border may fall on the other side in the brute-force count (deskew() rounds
  // differently): a few cells differ by a point.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> xy(-15.0f, 15.0f), z(-2.0f, 1.0f), t(0.0f, 0.1f);
  PointCloud points(200000);
  std::vector<float> times(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    points[i] = Eigen::Vector3f(xy(rng), xy(rng), z(rng));
    times[i] = t(rng);
  }
  Vector6d velocity;
  velocity << 8.0, 0.5, 0.0, 0.0, 0.0, 0.4;
  const SweepMotion motion(times, velocity);
  DloParams params;
  params.grid.min_points = 1;
  params.selection.centroid_levels = 2;
  HeightFrame f;
  f.build(points, motion, params.grid, params.selection, false, FrameUse::kCurrentAndReference);
  const PointCloud moved = deskew(points, motion);
  for (int k = 0; k < 2; ++k) {
    const FrameLevel& level = f.levels()[static_cast<size_t>(k)];
    const GridGeometry& geo = level.grid.geometry();
    std::vector<Eigen::Vector3d> sums(static_cast<size_t>(geo.cellCount()),
                                      Eigen::Vector3d::Zero());
    for (const Eigen::Vector3f& p : moved) {
      const double u = geo.u(p.x()), v = geo.v(p.y());
      if (u < 0 || v < 0 || u >= geo.cols || v >= geo.rows || p.z() < params.grid.min_z ||
          p.z() > params.grid.max_z)
        continue;
      sums[static_cast<size_t>(static_cast<int>(v) * geo.cols + static_cast<int>(u))] +=
          Eigen::Vector3d(p.x(), p.y(), 1.0);
    }
    int compared = 0, differ = 0;
    for (int r = 0; r < geo.rows; ++r) {
      for (int c = 0; c < geo.cols; ++c) {
        const Eigen::Vector3d& s = sums[static_cast<size_t>(r * geo.cols + c)];
        if (!level.grid.isValid(r, c) || s.z() < 3) continue;
        const Eigen::Vector2f off = level.grid_offsets[static_cast<size_t>(r * geo.cols + c)];
        const double e = std::max(std::abs(geo.cellCentreX(c) + off.x() - s.x() / s.z()),
                                  std::abs(geo.cellCentreY(r) + off.y() - s.y() / s.z()));
        differ += e > 2e-5 ? 1 : 0;
        ++compared;
      }
    }
    int selected = 0, selected_differ = 0;
    ASSERT_EQ(level.cell_offsets.size(), level.cells.size());
    for (size_t i = 0; i < level.cells.size(); ++i) {
      const SelectedCell& cell = level.cells[i];
      const Eigen::Vector3d& s = sums[static_cast<size_t>(
          static_cast<int>(geo.v(cell.y)) * geo.cols + static_cast<int>(geo.u(cell.x)))];
      if (s.z() < 1) continue;
      const double e = std::max(std::abs(cell.x + level.cell_offsets[i].x() - s.x() / s.z()),
                                std::abs(cell.y + level.cell_offsets[i].y() - s.y() / s.z()));
      selected_differ += e > 2e-5 ? 1 : 0;
      ++selected;
    }
    std::printf(
        "level %d: %d of %d cells and %d of %d selected cells differ by more than 0.02 mm\n", k,
        differ, compared, selected_differ, selected);
    EXPECT_GT(compared, 10000);
    EXPECT_GT(selected, 1000);
    EXPECT_LT(differ, compared / 200);
    EXPECT_LT(selected_differ, selected / 200);
  }
}

}  // namespace
}  // namespace dlo
