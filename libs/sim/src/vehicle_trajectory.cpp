#include "dlo/sim/vehicle_trajectory.h"

#include <cmath>

namespace dlo::sim {

VehicleTrajectory::VehicleTrajectory(const Route& route, const Terrain& terrain,
                                     const VehicleGeometry& geometry)
    : route_(route), terrain_(terrain), geometry_(geometry) {}

Eigen::Isometry3d VehicleTrajectory::vehiclePose(double t) const {
  const RouteState st = route_.stateAt(t);
  const Eigen::Vector2d f(std::cos(st.heading), std::sin(st.heading));
  const Eigen::Vector2d l(-f.y(), f.x());
  const double a = 0.5 * geometry_.wheelbase, b = 0.5 * geometry_.track;
  const auto wheel = [&](double sa, double sb) {
    const Eigen::Vector2d p = st.position + sa * a * f + sb * b * l;
    return Eigen::Vector3d(p.x(), p.y(), terrain_.heightAt(p.x(), p.y()));
  };
  const Eigen::Vector3d fl = wheel(1, 1), fr = wheel(1, -1), rl = wheel(-1, 1), rr = wheel(-1, -1);
  // Axes from the wheel contact points: forward = rear axle to front axle, then left made
  // orthogonal to it; the vehicle is rigid, so this is its best-fitting attitude.
  const Eigen::Vector3d x = (0.5 * (fl + fr) - 0.5 * (rl + rr)).normalized();
  const Eigen::Vector3d left = 0.5 * (fl + rl) - 0.5 * (fr + rr);
  const Eigen::Vector3d z = x.cross(left).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear().col(0) = x;
  pose.linear().col(1) = y;
  pose.linear().col(2) = z;
  pose.translation() =
      Eigen::Vector3d(st.position.x(), st.position.y(), 0.25 * (fl.z() + fr.z() + rl.z() + rr.z()));
  return pose;
}

Eigen::Isometry3d VehicleTrajectory::sensorMount() const {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.translation() = geometry_.sensorPosition;
  return m;
}

}  // namespace dlo::sim
