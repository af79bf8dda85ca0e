// The solid shapes the procedural world is built from, and ray intersection with them.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace dlo::sim {

/// What a surface is made of: decides the return intensity and lets tests tell hits apart.
enum class SurfaceClass : uint8_t {
  None = 0,
  Road,
  Sidewalk,
  Grass,
  Building,
  Roof,
  Trunk,
  Foliage,
  Pole,
  Car,
  MovingCar,
};

/// A shape in a local frame: translated to `centre` and rotated by `yaw` about +z.
enum class Shape : uint8_t {
  Box,        ///< |x| <= half.x, |y| <= half.y, |z| <= half.z.
  GableRoof,  ///< Box with the top cut by two planes: a ridge along local x at z = +half.z.
  Cylinder,   ///< Vertical: x^2 + y^2 <= half.x^2, |z| <= half.z.
  Ellipsoid,  ///< (x/half.x)^2 + (y/half.y)^2 + (z/half.z)^2 <= 1.
};

/// One solid object part.
struct Primitive {
  Shape shape = Shape::Box;
  SurfaceClass surface = SurfaceClass::Building;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d half = Eigen::Vector3d::Ones();  ///< Half extents or radii [m].
  double cosYaw = 1.0, sinYaw = 0.0;

  /// Sets the rotation about +z.
  void setYaw(double yaw);
  /// Radius of a vertical cylinder around `centre` that contains the shape (for culling).
  double horizontalRadius() const;
  /// Half size of the world-frame axis-aligned box that contains the shape in x and y.
  Eigen::Vector2d horizontalHalfExtent() const;
};

/// Makes a primitive; yaw in radians.
Primitive makePrimitive(Shape shape, SurfaceClass surface, const Eigen::Vector3d& centre,
                        const Eigen::Vector3d& half, double yaw = 0.0);

/**
 * Distance along the ray (origin + t * dir, dir of unit length) to the first surface point of
 * `p` with t in [tmin, tmax], or a negative value if there is none. A ray starting inside a
 * solid hits its exit surface.
 */
double intersectPrimitive(const Primitive& p, const Eigen::Vector3d& origin,
                          const Eigen::Vector3d& dir, double tmin, double tmax);

}  // namespace dlo::sim
