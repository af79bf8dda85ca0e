#include "dlo/sim/terrain.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dlo::sim {

namespace {

double pointSegmentDistance(const Eigen::Vector2d& p, const RoadSegment& s) {
  const Eigen::Vector2d ab = s.b - s.a;
  const double len2 = ab.squaredNorm();
  double u = len2 > 0.0 ? (p - s.a).dot(ab) / len2 : 0.0;
  u = std::clamp(u, 0.0, 1.0);
  return (p - (s.a + u * ab)).norm();
}

}  // namespace

Terrain::Terrain(const TerrainParams& params) : params_(params) {
  const double res = params_.gridResolution;
  nx_ = static_cast<int>(std::ceil((params_.gridMax.x() - params_.gridMin.x()) / res)) + 1;
  ny_ = static_cast<int>(std::ceil((params_.gridMax.y() - params_.gridMin.y()) / res)) + 1;
  hills_.resize(static_cast<size_t>(nx_) * ny_);
  road_.resize(hills_.size());
  for (int j = 0; j < ny_; ++j) {
    for (int i = 0; i < nx_; ++i) {
      const double x = params_.gridMin.x() + i * res, y = params_.gridMin.y() + j * res;
      const size_t k = static_cast<size_t>(j) * nx_ + i;
      hills_[k] = static_cast<float>(hillsExact(x, y));
      // Capped so that float keeps centimetre precision near the kerbs.
      road_[k] = static_cast<float>(std::min(roadDistanceExact(x, y), 1e4));
    }
  }
  for (const auto& w : params_.hills)
    slopeBound_ += std::abs(w.amplitude) * 2.0 * M_PI / w.wavelength;
  if (!params_.roads.empty()) slopeBound_ += 2.0 * params_.crownHeight / params_.roadHalfWidth;
  // Bilinear interpolation does not steepen a field, but float rounding can; keep a margin.
  slopeBound_ = slopeBound_ * 1.05 + 1e-4;
}

double Terrain::hillsExact(double x, double y) const {
  double h = 0.0;
  for (const auto& w : params_.hills) {
    const double u = w.direction.x() * x + w.direction.y() * y;
    h += w.amplitude * std::sin(2.0 * M_PI * u / w.wavelength + w.phase);
  }
  return h;
}

double Terrain::roadDistanceExact(double x, double y) const {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& s : params_.roads) d = std::min(d, pointSegmentDistance({x, y}, s));
  return d;
}

void Terrain::sample(double x, double y, double& hills, double& road) const {
  const double res = params_.gridResolution;
  const double gx = (x - params_.gridMin.x()) / res, gy = (y - params_.gridMin.y()) / res;
  if (!(gx >= 0.0 && gy >= 0.0 && gx < nx_ - 1 && gy < ny_ - 1)) {
    hills = hillsExact(x, y);
    road = roadDistanceExact(x, y);
    return;
  }
  const int i = static_cast<int>(gx), j = static_cast<int>(gy);
  const double fx = gx - i, fy = gy - j;
  const size_t k = static_cast<size_t>(j) * nx_ + i;
  const auto lerp2 = [&](const std::vector<float>& g) {
    const double a = g[k] + fx * (g[k + 1] - g[k]);
    const double b = g[k + nx_] + fx * (g[k + nx_ + 1] - g[k + nx_]);
    return a + fy * (b - a);
  };
  hills = lerp2(hills_);
  road = lerp2(road_);
}

double Terrain::groundFrom(double hills, double road) const {
  const double w = params_.roadHalfWidth;
  if (road >= w) return hills;
  const double r = road / w;
  return hills - params_.curbHeight + params_.crownHeight * (1.0 - r * r);
}

double Terrain::heightAt(double x, double y) const {
  double h, r;
  sample(x, y, h, r);
  return groundFrom(h, r);
}

double Terrain::roadDistance(double x, double y) const {
  double h, r;
  sample(x, y, h, r);
  return r;
}

SurfaceClass Terrain::surfaceAt(double x, double y) const {
  const double r = roadDistance(x, y);
  if (r < params_.roadHalfWidth) return SurfaceClass::Road;
  if (r < params_.roadHalfWidth + params_.sidewalkWidth) return SurfaceClass::Sidewalk;
  return SurfaceClass::Grass;
}

Eigen::Vector3d Terrain::normalAt(double x, double y) const {
  // Central differences of the smooth part only: the kerb step is not a slope.
  const double e = 0.25;
  const auto smooth = [&](double px, double py) {
    double h, r;
    sample(px, py, h, r);
    const double w = params_.roadHalfWidth;
    if (r >= w) return h;
    const double q = r / w;
    return h + params_.crownHeight * (1.0 - q * q);
  };
  const double gx = (smooth(x + e, y) - smooth(x - e, y)) / (2 * e);
  const double gy = (smooth(x, y + e) - smooth(x, y - e)) / (2 * e);
  return Eigen::Vector3d(-gx, -gy, 1.0).normalized();
}

double Terrain::intersectRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                             double tmax) const {
  const double w = params_.roadHalfWidth;
  const double curb = params_.curbHeight;
  const double horiz = std::hypot(dir.x(), dir.y());
  // Rate at which the gap between ray and ground can shrink per unit t.
  const double rate = slopeBound_ * horiz - dir.z();
  constexpr double kMinStep = 0.05;

  const auto gapAt = [&](double t, double& road) {
    double h;
    sample(origin.x() + t * dir.x(), origin.y() + t * dir.y(), h, road);
    return origin.z() + t * dir.z() - groundFrom(h, road);
  };

  double t = 0.0, road;
  double gap = gapAt(t, road);
  if (gap < 0.0) return -1.0;  // Starts underground: no sensible return.
  double tPrev = t;
  while (true) {
    // Going from road to sidewalk raises the ground by the curb height; nothing else jumps.
    double step;
    const bool onRoad = road < w;
    if (rate <= 0.0) {
      if (!onRoad || gap > curb) return -1.0;  // The ray climbs faster than any slope.
      step = kMinStep;
    } else {
      step = gap / rate;
      if (onRoad) {
        const double toEdge = horiz > 1e-9 ? (w - road) / horiz : 1e300;
        step = std::max(std::min(step, toEdge), (gap - curb) / rate);
      }
      step = std::max(step, kMinStep);
    }
    tPrev = t;
    t += step;
    if (t > tmax) {
      t = tmax;
      if (tPrev >= tmax) return -1.0;
    }
    gap = gapAt(t, road);
    if (gap < 0.0) break;
    if (t >= tmax) return -1.0;
  }
  // Bisection keeps the kerb face sharp, where a secant step would smear it.
  double lo = tPrev, hi = t;
  while (hi - lo > 2e-4) {
    const double mid = 0.5 * (lo + hi);
    if (gapAt(mid, road) < 0.0) {
      hi = mid;
    } else {
      lo = mid;
    }
  }
  return 0.5 * (lo + hi);
}

}  // namespace dlo::sim
