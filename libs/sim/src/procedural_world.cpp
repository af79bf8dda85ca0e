#include "dlo/sim/procedural_world.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dlo/sim/deterministic_random.h"

namespace dlo::sim {

ProceduralWorld::ProceduralWorld(Terrain terrain, std::vector<Primitive> objects, Traffic traffic,
                                 double cellSize)
    : terrain_(std::move(terrain)),
      objects_(std::move(objects), cellSize),
      traffic_(std::move(traffic)) {}

namespace {

/// Everything generate() and generateOpenRoad() need while placing objects.
struct Builder {
  const Terrain& terrain;
  DeterministicRng& rng;
  std::vector<Primitive> out;

  double ground(double x, double y) const { return terrain.heightAt(x, y); }

  /// Lowest ground under a rectangle, so that objects on a slope do not float.
  double lowestGround(const Eigen::Vector2d& c, const Eigen::Vector2d& half, double yaw) const {
    double z = 1e300;
    for (int sx = -1; sx <= 1; sx += 2) {
      for (int sy = -1; sy <= 1; sy += 2) {
        const double lx = sx * half.x(), ly = sy * half.y();
        z = std::min(z, ground(c.x() + std::cos(yaw) * lx - std::sin(yaw) * ly,
                               c.y() + std::sin(yaw) * lx + std::cos(yaw) * ly));
      }
    }
    return std::min(z, ground(c.x(), c.y()));
  }

  void box(SurfaceClass s, const Eigen::Vector2d& c, const Eigen::Vector2d& half, double z0,
           double z1, double yaw = 0.0) {
    out.push_back(makePrimitive(Shape::Box, s, Eigen::Vector3d(c.x(), c.y(), 0.5 * (z0 + z1)),
                                Eigen::Vector3d(half.x(), half.y(), 0.5 * (z1 - z0)), yaw));
  }

  /// A building on the footprint [lo, hi]: flat or pitched roof, sometimes L-shaped.
  void building(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
    const Eigen::Vector2d size = hi - lo;
    const double height = rng.uniform(5.0, 18.0);
    const bool lShaped = rng.bernoulli(0.35) && size.minCoeff() > 10.0;
    const bool pitched = rng.bernoulli(0.4);
    // Main wing: the whole footprint, or its front part for an L.
    Eigen::Vector2d mLo = lo, mHi = hi;
    if (lShaped) mHi.y() = lo.y() + size.y() * rng.uniform(0.4, 0.6);
    const Eigen::Vector2d mc = 0.5 * (mLo + mHi), mh = 0.5 * (mHi - mLo);
    const double base = lowestGround(mc, mh, 0.0) - 0.3;
    box(SurfaceClass::Building, mc, mh, base, base + 0.3 + height);
    if (pitched) {
      const double roof = rng.uniform(2.0, 4.0);
      // Ridge along the longer side.
      const bool alongX = mh.x() >= mh.y();
      const Eigen::Vector3d half = alongX ? Eigen::Vector3d(mh.x(), mh.y(), 0.5 * roof)
                                          : Eigen::Vector3d(mh.y(), mh.x(), 0.5 * roof);
      out.push_back(makePrimitive(Shape::GableRoof, SurfaceClass::Roof,
                                  Eigen::Vector3d(mc.x(), mc.y(), base + 0.3 + height + 0.5 * roof),
                                  half, alongX ? 0.0 : M_PI / 2));
    }
    if (lShaped) {
      // Wing along one side, from the main wing to the back of the footprint.
      const double wingWidth = size.x() * rng.uniform(0.3, 0.5);
      const bool left = rng.bernoulli(0.5);
      const Eigen::Vector2d wLo(left ? lo.x() : hi.x() - wingWidth, mHi.y());
      const Eigen::Vector2d wHi(left ? lo.x() + wingWidth : hi.x(), hi.y());
      const Eigen::Vector2d wc = 0.5 * (wLo + wHi), wh = 0.5 * (wHi - wLo);
      const double wbase = lowestGround(wc, wh, 0.0) - 0.3;
      box(SurfaceClass::Building, wc, wh, wbase, base + 0.3 + height * rng.uniform(0.6, 1.0));
    }
  }

  void tree(const Eigen::Vector2d& c) {
    const double z = ground(c.x(), c.y());
    const double trunkHeight = rng.uniform(2.5, 4.0);
    const double trunkRadius = rng.uniform(0.12, 0.25);
    const double rh = rng.uniform(2.0, 3.5), rv = rng.uniform(1.5, 2.5);
    out.push_back(
        makePrimitive(Shape::Cylinder, SurfaceClass::Trunk,
                      Eigen::Vector3d(c.x(), c.y(), z + 0.5 * trunkHeight - 0.2),
                      Eigen::Vector3d(trunkRadius, trunkRadius, 0.5 * trunkHeight + 0.2)));
    out.push_back(makePrimitive(
        Shape::Ellipsoid, SurfaceClass::Foliage,
        Eigen::Vector3d(c.x(), c.y(), z + trunkHeight + 0.8 * rv),
        Eigen::Vector3d(rh * rng.uniform(0.85, 1.15), rh * rng.uniform(0.85, 1.15), rv),
        rng.uniform(0.0, M_PI)));
  }

  void bush(const Eigen::Vector2d& c) {
    const double rz = rng.uniform(0.3, 0.6);
    out.push_back(makePrimitive(Shape::Ellipsoid, SurfaceClass::Foliage,
                                Eigen::Vector3d(c.x(), c.y(), ground(c.x(), c.y()) + 0.6 * rz),
                                Eigen::Vector3d(rng.uniform(0.5, 1.5), rng.uniform(0.5, 1.5), rz),
                                rng.uniform(0.0, M_PI)));
  }

  void pole(const Eigen::Vector2d& c) {
    const double h = rng.uniform(6.0, 8.0);
    out.push_back(makePrimitive(Shape::Cylinder, SurfaceClass::Pole,
                                Eigen::Vector3d(c.x(), c.y(), ground(c.x(), c.y()) + 0.5 * h - 0.2),
                                Eigen::Vector3d(0.12, 0.12, 0.5 * h + 0.2)));
  }
};

/// Three gentle hill waves of 200, 110 and 45 m (each +-10 %) in random directions, the longest
/// of `amplitude`.
std::vector<HillWave> gentleHills(DeterministicRng& rng, double amplitude) {
  const double amplitudes[3] = {amplitude, 0.45 * amplitude, 0.12 * amplitude};
  const double wavelengths[3] = {200.0, 110.0, 45.0};
  std::vector<HillWave> hills;
  for (int k = 0; k < 3; ++k) {
    const double a = rng.uniform(0.0, 2.0 * M_PI);
    hills.push_back({amplitudes[k], wavelengths[k] * rng.uniform(0.9, 1.1),
                     Eigen::Vector2d(std::cos(a), std::sin(a)), rng.uniform(0.0, 2.0 * M_PI)});
  }
  return hills;
}

bool nearAny(double v, const std::vector<double>& lines, double margin) {
  for (double l : lines) {
    if (std::abs(v - l) < margin) return true;
  }
  return false;
}

}  // namespace

std::vector<HillWave> steepHills(double maxGrade, const TerrainParams& ground, uint32_t seed) {
  // The crown's grade (2 crown / half width, at the kerbs) adds to the hills' anywhere on a road.
  const double budget = maxGrade - 2.0 * ground.crownHeight / ground.roadHalfWidth;
  if (!(budget > 0.0 && std::isfinite(budget)))
    throw std::invalid_argument("steepHills: the grade must exceed the road crown's");
  DeterministicRng rng({seed, 0x48494c4cu});  // "HILL"
  // A wave's grade is amplitude * 2 pi / wavelength; the three together stay within the budget
  // in any direction, since a sum of grades is at most the sum of their bounds.
  const auto wave = [&](double share, double wavelength, double direction) {
    return HillWave{share * budget * wavelength / (2.0 * M_PI), wavelength,
                    Eigen::Vector2d(std::cos(direction), std::sin(direction)),
                    rng.uniform(0.0, 2.0 * M_PI)};
  };
  std::vector<HillWave> hills;
  hills.push_back(wave(0.8, rng.uniform(48.0, 62.0), 0.0));
  hills.push_back(wave(0.15, rng.uniform(70.0, 90.0), 0.5 * M_PI));
  hills.push_back(wave(0.05, rng.uniform(35.0, 45.0), rng.uniform(0.0, 2.0 * M_PI)));
  return hills;
}

ProceduralWorld ProceduralWorld::generate(uint32_t seed, const WorldParams& p) {
  DeterministicRng rng({seed, 0x574f524cu});  // "WORL": a stream of its own.

  TerrainParams tp;
  // Drawn even when steep hills replace them, so that the objects are the same town's.
  tp.hills = gentleHills(rng, p.hillAmplitude);
  if (p.maxGrade > 0.0) tp.hills = steepHills(p.maxGrade, tp, seed);
  const double x0 = p.roadsX.front() - p.roadExtension, x1 = p.roadsX.back() + p.roadExtension;
  const double y0 = p.roadsY.front() - p.roadExtension, y1 = p.roadsY.back() + p.roadExtension;
  for (double x : p.roadsX) tp.roads.push_back({{x, y0}, {x, y1}});
  for (double y : p.roadsY) tp.roads.push_back({{x0, y}, {x1, y}});
  tp.gridMin = p.loopMin - Eigen::Vector2d::Constant(p.gridMargin);
  tp.gridMax = p.loopMax + Eigen::Vector2d::Constant(p.gridMargin);
  Terrain terrain(tp);

  Builder b{terrain, rng, {}};
  const double w = tp.roadHalfWidth, sidewalk = tp.sidewalkWidth;

  // Blocks between roads: lots with buildings or small parks.
  for (size_t i = 0; i + 1 < p.roadsX.size(); ++i) {
    for (size_t j = 0; j + 1 < p.roadsY.size(); ++j) {
      const double inset = w + sidewalk + 1.0;
      const Eigen::Vector2d lo(p.roadsX[i] + inset, p.roadsY[j] + inset);
      const Eigen::Vector2d hi(p.roadsX[i + 1] - inset, p.roadsY[j + 1] - inset);
      const int lots = rng.integer(2, 3);
      const double lotW = (hi.x() - lo.x()) / lots;
      for (int k = 0; k < lots; ++k) {
        const Eigen::Vector2d llo(lo.x() + k * lotW, lo.y()), lhi(lo.x() + (k + 1) * lotW, hi.y());
        if (rng.bernoulli(0.8)) {
          const Eigen::Vector2d blo =
              llo + Eigen::Vector2d(rng.uniform(0.5, 2.0), rng.uniform(0.5, 3.0));
          const Eigen::Vector2d bhi =
              lhi - Eigen::Vector2d(rng.uniform(0.5, 2.0), rng.uniform(0.5, 3.0));
          b.building(blo, bhi);
          // A hedge of bushes in front of some buildings.
          if (rng.bernoulli(0.5)) {
            for (double x = llo.x() + 1.0; x < lhi.x() - 1.0; x += rng.uniform(2.0, 4.0))
              b.bush({x, llo.y() - 0.2});
          }
        } else {
          const int trees = rng.integer(2, 5), bushes = rng.integer(3, 8);
          for (int n = 0; n < trees; ++n)
            b.tree({rng.uniform(llo.x() + 2, lhi.x() - 2), rng.uniform(llo.y() + 2, lhi.y() - 2)});
          for (int n = 0; n < bushes; ++n)
            b.bush({rng.uniform(llo.x() + 1, lhi.x() - 1), rng.uniform(llo.y() + 1, lhi.y() - 1)});
        }
      }
    }
  }

  // Along every road: trees and poles on the sidewalks, parked cars at the kerbs. With a
  // traffic seed of its own, the cars are drawn from that stream; the town's stream is still
  // drawn exactly as without it, so that every other object stays where it was.
  std::vector<MovingCar> moving;
  DeterministicRng traffic({p.trafficSeed, 0x54524146u});  // "TRAF"
  const bool ownTraffic = p.trafficSeed != 0;
  const auto loopRoad = [&](bool alongX, double line) {
    return alongX ? (line == p.loopMin.y() || line == p.loopMax.y())
                  : (line == p.loopMin.x() || line == p.loopMax.x());
  };
  for (int axis = 0; axis < 2; ++axis) {
    const bool alongX = axis == 0;  // East-west roads run along x.
    const auto& lines = alongX ? p.roadsY : p.roadsX;
    const auto& crossing = alongX ? p.roadsX : p.roadsY;
    const double from = alongX ? x0 : y0, to = alongX ? x1 : y1;
    for (double line : lines) {
      const auto at = [&](double s, double offset) {
        return alongX ? Eigen::Vector2d(s, line + offset) : Eigen::Vector2d(line + offset, s);
      };
      const bool isLoop = loopRoad(alongX, line);
      // The loop block's side of a loop road: parked cars only there, traffic on the other.
      const double inside =
          alongX ? (line == p.loopMin.y() ? 1.0 : -1.0) : (line == p.loopMin.x() ? 1.0 : -1.0);
      for (int side = -1; side <= 1; side += 2) {
        for (double s = from + rng.uniform(0.0, 8.0); s < to; s += rng.uniform(9.0, 14.0)) {
          if (!nearAny(s, crossing, w + 4.0) && rng.bernoulli(0.65))
            b.tree(at(s, side * (w + rng.uniform(1.0, 1.8))));
        }
        for (double s = from + rng.uniform(0.0, 30.0); s < to; s += rng.uniform(25.0, 35.0)) {
          if (!nearAny(s, crossing, w + 1.0)) b.pole(at(s, side * (w + 0.5)));
        }
        if (isLoop && side != inside) continue;
        const auto parkCars = [&](DeterministicRng& r, bool place) {
          for (double s = from; s < to; s += r.uniform(6.5, 9.0)) {
            if (nearAny(s, crossing, w + 9.0) || !r.bernoulli(0.35)) continue;
            const Eigen::Vector2d c = at(s, side * (w - 1.0));
            const double yaw =
                (alongX ? 0.0 : M_PI / 2) + (side > 0 ? 0.0 : M_PI) + r.uniform(-0.04, 0.04);
            if (!place) continue;
            appendCarPrimitives(Eigen::Vector3d(c.x(), c.y(), terrain.heightAt(c.x(), c.y())), yaw,
                                SurfaceClass::Car, b.out);
          }
        };
        parkCars(rng, !ownTraffic);
        if (ownTraffic) parkCars(traffic, true);
      }
      // Two moving cars per road, one per lane; on loop roads a single one on the outer lane,
      // clear of the vehicle's path.
      for (int n = 0; n < (isLoop ? 1 : 2); ++n) {
        const double dirSign = n == 0 ? 1.0 : -1.0;
        const double offset = isLoop ? -inside * 2.4 : -dirSign * 2.0;
        const Eigen::Vector2d u =
            alongX ? Eigen::Vector2d(dirSign, 0) : Eigen::Vector2d(0, dirSign);
        const Eigen::Vector2d start = dirSign > 0 ? at(from, offset) : at(to, offset);
        const double speed = rng.uniform(6.0, 12.0), phase = rng.uniform(0.0, to - from);
        if (ownTraffic) {
          moving.push_back(
              {start, u, to - from, traffic.uniform(6.0, 12.0), traffic.uniform(0.0, to - from)});
        } else {
          moving.push_back({start, u, to - from, speed, phase});
        }
      }
    }
  }
  return ProceduralWorld(std::move(terrain), std::move(b.out), Traffic(std::move(moving)),
                         p.objectCellSize);
}

ProceduralWorld ProceduralWorld::generateOpenRoad(uint32_t seed, const OpenRoadParams& p) {
  DeterministicRng rng({seed, 0x524f4144u});  // "ROAD": not the town's stream.
  TerrainParams tp;
  tp.hills =
      p.maxGrade > 0.0 ? steepHills(p.maxGrade, tp, seed) : gentleHills(rng, p.hillAmplitude);
  const Eigen::Vector2d lo = p.loopMin, hi = p.loopMax;
  const double ext = 30.0;
  tp.roads = {{{lo.x() - ext, lo.y()}, {hi.x() + ext, lo.y()}},
              {{lo.x() - ext, hi.y()}, {hi.x() + ext, hi.y()}},
              {{lo.x(), lo.y() - ext}, {lo.x(), hi.y() + ext}},
              {{hi.x(), lo.y() - ext}, {hi.x(), hi.y() + ext}}};
  tp.gridMin = lo - Eigen::Vector2d::Constant(p.gridMargin);
  tp.gridMax = hi + Eigen::Vector2d::Constant(p.gridMargin);
  Terrain terrain(tp);

  Builder b{terrain, rng, {}};
  const double w = tp.roadHalfWidth;
  for (const RoadSegment& road : tp.roads) {
    const Eigen::Vector2d along = (road.b - road.a).normalized();
    const Eigen::Vector2d left(-along.y(), along.x());
    // Outward from the rectangle: the side away from its centre.
    const double outer = left.dot(0.5 * (lo + hi) - road.a) > 0.0 ? -1.0 : 1.0;
    const double length = (road.b - road.a).norm();
    const auto at = [&](double s, double offset) -> Eigen::Vector2d {
      return road.a + s * along + offset * left;
    };
    // Clear of the crossings at both ends, where the other road's poles stand.
    const double from = ext + w + 1.0, to = length - ext - w - 1.0;
    for (double s = from + rng.uniform(0.0, p.poleSpacing); s < to;
         s += p.poleSpacing * rng.uniform(0.6, 1.4))
      b.pole(at(s, outer * (w + tp.sidewalkWidth + 0.5)));
    for (double s = from + rng.uniform(0.0, p.copseSpacing); s < to;
         s += p.copseSpacing * rng.uniform(0.5, 1.5)) {
      const double side = rng.bernoulli(0.5) ? 1.0 : -1.0;
      const Eigen::Vector2d c = at(s, side * rng.uniform(w + 10.0, w + 40.0));
      const int trees = rng.integer(1, 3), bushes = rng.integer(0, 3);
      for (int n = 0; n < trees; ++n)
        b.tree(c + Eigen::Vector2d(rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0)));
      for (int n = 0; n < bushes; ++n)
        b.bush(c + Eigen::Vector2d(rng.uniform(-6.0, 6.0), rng.uniform(-6.0, 6.0)));
    }
  }
  return ProceduralWorld(std::move(terrain), std::move(b.out), Traffic(), p.objectCellSize);
}

}  // namespace dlo::sim
