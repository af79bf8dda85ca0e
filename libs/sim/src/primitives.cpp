#include "dlo/sim/primitives.h"

#include <algorithm>
#include <cmath>

namespace dlo::sim {

void Primitive::setYaw(double yaw) {
  cosYaw = std::cos(yaw);
  sinYaw = std::sin(yaw);
}

double Primitive::horizontalRadius() const {
  switch (shape) {
    case Shape::Cylinder:
      return half.x();
    case Shape::Ellipsoid:
      return std::max(half.x(), half.y());
    default:
      return std::hypot(half.x(), half.y());
  }
}

Eigen::Vector2d Primitive::horizontalHalfExtent() const {
  if (shape == Shape::Cylinder) return Eigen::Vector2d(half.x(), half.x());
  const double c = std::abs(cosYaw), s = std::abs(sinYaw);
  return Eigen::Vector2d(c * half.x() + s * half.y(), s * half.x() + c * half.y());
}

Primitive makePrimitive(Shape shape, SurfaceClass surface, const Eigen::Vector3d& centre,
                        const Eigen::Vector3d& half, double yaw) {
  Primitive p;
  p.shape = shape;
  p.surface = surface;
  p.centre = centre;
  p.half = half;
  p.setYaw(yaw);
  return p;
}

namespace {

constexpr double kNone = -1.0;

/// First root >= tmin of the entry/exit interval [t0, t1], clipped to tmax.
double firstInRange(double t0, double t1, double tmin, double tmax) {
  if (t1 < t0 || t1 < tmin || t0 > tmax) return kNone;
  if (t0 >= tmin) return t0;
  return t1 <= tmax ? t1 : kNone;
}

/// Clips [t0, t1] by the half space n.p <= c; false if it becomes empty.
bool clipByPlane(const Eigen::Vector3d& n, double c, const Eigen::Vector3d& o,
                 const Eigen::Vector3d& d, double& t0, double& t1) {
  const double denom = n.dot(d);
  const double dist = c - n.dot(o);
  if (std::abs(denom) < 1e-15) return dist >= 0.0;
  const double t = dist / denom;
  if (denom > 0.0) {
    t1 = std::min(t1, t);
  } else {
    t0 = std::max(t0, t);
  }
  return t0 <= t1;
}

double intersectBox(const Eigen::Vector3d& h, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                    double tmin, double tmax) {
  double t0 = -1e300, t1 = 1e300;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-15) {
      if (std::abs(o[k]) > h[k]) return kNone;
      continue;
    }
    const double inv = 1.0 / d[k];
    double a = (-h[k] - o[k]) * inv, b = (h[k] - o[k]) * inv;
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return kNone;
  }
  return firstInRange(t0, t1, tmin, tmax);
}

double intersectGableRoof(const Eigen::Vector3d& h, const Eigen::Vector3d& o,
                          const Eigen::Vector3d& d, double tmin, double tmax) {
  // The enclosing box, then the two roof planes z + (2 h.z / h.y) |y| <= h.z.
  double t0 = -1e300, t1 = 1e300;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    n[k] = 1.0;
    if (!clipByPlane(n, h[k], o, d, t0, t1)) return kNone;
    if (!clipByPlane(-n, h[k], o, d, t0, t1)) return kNone;
  }
  const double slope = 2.0 * h.z() / h.y();
  if (!clipByPlane(Eigen::Vector3d(0.0, slope, 1.0), h.z(), o, d, t0, t1)) return kNone;
  if (!clipByPlane(Eigen::Vector3d(0.0, -slope, 1.0), h.z(), o, d, t0, t1)) return kNone;
  return firstInRange(t0, t1, tmin, tmax);
}

double intersectCylinder(const Eigen::Vector3d& h, const Eigen::Vector3d& o,
                         const Eigen::Vector3d& d, double tmin, double tmax) {
  double t0 = -1e300, t1 = 1e300;
  const double a = d.x() * d.x() + d.y() * d.y();
  const double b = o.x() * d.x() + o.y() * d.y();
  const double c = o.x() * o.x() + o.y() * o.y() - h.x() * h.x();
  if (a < 1e-15) {
    if (c > 0.0) return kNone;
  } else {
    const double disc = b * b - a * c;
    if (disc < 0.0) return kNone;
    const double sq = std::sqrt(disc);
    t0 = (-b - sq) / a;
    t1 = (-b + sq) / a;
  }
  if (!clipByPlane(Eigen::Vector3d::UnitZ(), h.z(), o, d, t0, t1)) return kNone;
  if (!clipByPlane(-Eigen::Vector3d::UnitZ(), h.z(), o, d, t0, t1)) return kNone;
  return firstInRange(t0, t1, tmin, tmax);
}

double intersectEllipsoid(const Eigen::Vector3d& h, const Eigen::Vector3d& o,
                          const Eigen::Vector3d& d, double tmin, double tmax) {
  // In coordinates scaled to the unit sphere t keeps its meaning: p = o' + t d'.
  const Eigen::Vector3d os = o.cwiseQuotient(h), ds = d.cwiseQuotient(h);
  const double a = ds.squaredNorm(), b = os.dot(ds), c = os.squaredNorm() - 1.0;
  const double disc = b * b - a * c;
  if (disc < 0.0) return kNone;
  const double sq = std::sqrt(disc);
  return firstInRange((-b - sq) / a, (-b + sq) / a, tmin, tmax);
}

}  // namespace

double intersectPrimitive(const Primitive& p, const Eigen::Vector3d& origin,
                          const Eigen::Vector3d& dir, double tmin, double tmax) {
  // Into the local frame: rotate by -yaw about the centre.
  const Eigen::Vector3d q = origin - p.centre;
  const Eigen::Vector3d o(p.cosYaw * q.x() + p.sinYaw * q.y(), -p.sinYaw * q.x() + p.cosYaw * q.y(),
                          q.z());
  const Eigen::Vector3d d(p.cosYaw * dir.x() + p.sinYaw * dir.y(),
                          -p.sinYaw * dir.x() + p.cosYaw * dir.y(), dir.z());
  switch (p.shape) {
    case Shape::Box:
      return intersectBox(p.half, o, d, tmin, tmax);
    case Shape::GableRoof:
      return intersectGableRoof(p.half, o, d, tmin, tmax);
    case Shape::Cylinder:
      return intersectCylinder(p.half, o, d, tmin, tmax);
    case Shape::Ellipsoid:
      return intersectEllipsoid(p.half, o, d, tmin, tmax);
  }
  return kNone;
}

}  // namespace dlo::sim
