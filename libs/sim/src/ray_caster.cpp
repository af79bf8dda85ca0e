#include "dlo/sim/ray_caster.h"

namespace dlo::sim {

RayHit RayCaster::cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double maxRange,
                       const std::vector<Primitive>& dynamic, GridScratch& scratch) const {
  RayHit best;
  // The ground first: most rays hit it, and its distance bounds the object search.
  const double tg = world_.terrain().intersectRay(origin, dir, maxRange);
  if (tg >= 0.0) {
    const Eigen::Vector3d p = origin + tg * dir;
    best.t = tg;
    best.surface = world_.terrain().surfaceAt(p.x(), p.y());
  }
  const double limit = best.valid() ? best.t : maxRange;
  const RayHit obj = world_.objects().intersect(origin, dir, 0.0, limit, scratch);
  if (obj.valid() && (!best.valid() || obj.t < best.t)) best = obj;

  for (const auto& car : dynamic) {
    // Cheap rejection by the bounding sphere before the exact test.
    const double lim = best.valid() ? best.t : maxRange;
    const Eigen::Vector3d oc = car.centre - origin;
    const double along = oc.dot(dir);
    const double r = car.half.norm();
    if (along < -r || along > lim + r) continue;
    if ((oc - along * dir).squaredNorm() > r * r) continue;
    const double t = intersectPrimitive(car, origin, dir, 0.0, lim);
    if (t >= 0.0) {
      best.t = t;
      best.surface = car.surface;
    }
  }
  return best;
}

}  // namespace dlo::sim
