#include "dlo/sim/traffic.h"

#include <cmath>

namespace dlo::sim {

void appendCarPrimitives(const Eigen::Vector3d& ground, double yaw, SurfaceClass surface,
                         std::vector<Primitive>& out) {
  const Eigen::Vector3d forward(std::cos(yaw), std::sin(yaw), 0.0);
  out.push_back(makePrimitive(Shape::Box, surface, ground + Eigen::Vector3d(0, 0, 0.625),
                              Eigen::Vector3d(2.25, 0.9, 0.375), yaw));
  out.push_back(makePrimitive(Shape::Box, surface,
                              ground - 0.3 * forward + Eigen::Vector3d(0, 0, 1.25),
                              Eigen::Vector3d(1.25, 0.8, 0.25), yaw));
}

void appendTruckPrimitives(const Eigen::Vector3d& ground, double yaw, SurfaceClass surface,
                           std::vector<Primitive>& out) {
  const Eigen::Vector3d forward(std::cos(yaw), std::sin(yaw), 0.0);
  out.push_back(makePrimitive(Shape::Box, surface,
                              ground - 1.25 * forward + Eigen::Vector3d(0, 0, 2.2),
                              Eigen::Vector3d(3.75, 1.25, 1.4), yaw));
  out.push_back(makePrimitive(Shape::Box, surface,
                              ground + 3.8 * forward + Eigen::Vector3d(0, 0, 1.45),
                              Eigen::Vector3d(1.1, 1.2, 1.05), yaw));
}

void Traffic::primitivesAt(double t, const Terrain& terrain, const Eigen::Vector2d& near,
                           double radius, std::vector<Primitive>& out) const {
  out.clear();
  for (const auto& car : cars_) {
    double s = std::fmod(car.phase + car.speed * t, car.length);
    if (s < 0.0) s += car.length;
    const Eigen::Vector2d p = car.start + s * car.direction;
    if ((p - near).squaredNorm() > radius * radius) continue;
    const double yaw = std::atan2(car.direction.y(), car.direction.x());
    const Eigen::Vector3d ground(p.x(), p.y(), terrain.heightAt(p.x(), p.y()));
    if (car.truck) {
      appendTruckPrimitives(ground, yaw, SurfaceClass::MovingCar, out);
    } else {
      appendCarPrimitives(ground, yaw, SurfaceClass::MovingCar, out);
    }
  }
}

}  // namespace dlo::sim
