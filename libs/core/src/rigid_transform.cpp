#include "dlo/core/rigid_transform.h"

#include <cmath>

namespace dlo {

namespace {
Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}
}  // namespace

Eigen::Isometry3d expSE3(const Vector6d& xi) {
  const Eigen::Vector3d v = xi.head<3>();
  const Eigen::Vector3d w = xi.tail<3>();
  const double theta = w.norm();
  const Eigen::Matrix3d W = skew(w);
  // Below 1e-3 rad the series: 1 - cos(theta) loses most of its digits there (see logSE3).
  const double t2 = theta * theta;
  const bool small = theta < 1e-3;
  const double a = small ? 1.0 - t2 / 6.0 + t2 * t2 / 120.0 : std::sin(theta) / theta;
  const double b = small ? 0.5 - t2 / 24.0 + t2 * t2 / 720.0 : (1.0 - std::cos(theta)) / t2;
  const double c = small ? 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0 : (1.0 - a) / t2;
  const Eigen::Matrix3d R = Eigen::Matrix3d::Identity() + a * W + b * W * W;
  const Eigen::Matrix3d V = Eigen::Matrix3d::Identity() + b * W + c * W * W;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = V * v;
  return T;
}

Vector6d logSE3(const Eigen::Isometry3d& T) {
  const Eigen::AngleAxisd aa(T.linear());
  const double theta = aa.angle();
  const Eigen::Vector3d w = theta * aa.axis();
  const Eigen::Matrix3d W = skew(w);
  // V^-1 = I - W/2 + k W^2 with k = (1 - (theta/2) cot(theta/2)) / theta^2. Written as
  // sin/(1 - cos) it cancels catastrophically for rotations of 1e-9..1e-6 rad, which planar
  // 3-DoF poses produce all the time: 1 - cos(theta) rounds to a multiple of 2^-53 and k came
  // out wrong by orders of magnitude (a velocity 32 % too high in a simulated corridor). Below
  // 1e-3 rad the series is exact to double precision.
  const double t2 = theta * theta;
  const double k = theta < 1e-3 ? 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0
                                : (1.0 - 0.5 * theta / std::tan(0.5 * theta)) / t2;
  const Eigen::Matrix3d Vinv = Eigen::Matrix3d::Identity() - 0.5 * W + k * W * W;
  Vector6d xi;
  xi.head<3>() = Vinv * T.translation();
  xi.tail<3>() = w;
  return xi;
}

Eigen::Isometry3d poseFromXYZYPR(double x, double y, double z, double yaw, double pitch,
                                 double roll) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

Eigen::Vector3d yawPitchRoll(const Eigen::Matrix3d& R) {
  // R = Rz(y) Ry(p) Rx(r): R(2,0) = -sin(p).
  const double pitch = std::atan2(-R(2, 0), std::hypot(R(0, 0), R(1, 0)));
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  const double roll = std::atan2(R(2, 1), R(2, 2));
  return Eigen::Vector3d(yaw, pitch, roll);
}

}  // namespace dlo

namespace dlo {

namespace {
Vector6d xyzypr(const Eigen::Isometry3d& T) {
  Vector6d p;
  p.head<3>() = T.translation();
  p.tail<3>() = yawPitchRoll(T.linear());
  return p;
}
}  // namespace

Matrix6d twistCovarianceToXYZYPR(const Eigen::Isometry3d& pose, const Matrix6d& twist_cov) {
  constexpr double h = 1e-6;
  Matrix6d J;
  for (int k = 0; k < 6; ++k) {
    Vector6d d = Vector6d::Zero();
    d(k) = h;
    Vector6d diff = (xyzypr(expSE3(d) * pose) - xyzypr(expSE3(-d) * pose)) / (2 * h);
    for (int a = 3; a < 6; ++a) diff(a) = std::remainder(diff(a) * 2 * h, 2 * M_PI) / (2 * h);
    J.col(k) = diff;
  }
  return J * twist_cov * J.transpose();
}

}  // namespace dlo
