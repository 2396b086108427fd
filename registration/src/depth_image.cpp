/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/verification/depth_image.h>
#include <pcl/point_types.h>
#include <pcl_icf_internal/parameter_check.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace pcl {
namespace icf {

namespace {

[[noreturn]] void fail(const char* what, const char* field, double value, const char* rule) {
  const internal::ParameterCheck check(what);
  check(field, value, rule);
}

bool inFront(const Eigen::Vector3f& p) {
  return p.allFinite() && p.z() > 1e-6f;
}

/** Least-squares line pixel = f * tangent + c; false when the tangents do not vary. */
bool fitLine(const std::vector<std::pair<double, double>>& tangent_pixel, float& f, float& c,
             double& sum_sq) {
  const double n = static_cast<double>(tangent_pixel.size());
  double st = 0, sp = 0, stt = 0, stp = 0;
  for (const auto& [t, p] : tangent_pixel) {
    st += t;
    sp += p;
    stt += t * t;
    stp += t * p;
  }
  const double var = stt - st * st / n;
  if (!(var > 1e-12 * n))
    return false;
  const double slope = (stp - st * sp / n) / var;
  const double offset = (sp - slope * st) / n;
  for (const auto& [t, p] : tangent_pixel)
    sum_sq += (slope * t + offset - p) * (slope * t + offset - p);
  f = static_cast<float>(slope);
  c = static_cast<float>(offset);
  return true;
}

}  // namespace

void PinholeIntrinsics::validate() const {
  if (!(fx > 0.f) || !std::isfinite(fx))
    fail("PinholeIntrinsics", "fx", fx, "must be positive and finite");
  if (!(fy > 0.f) || !std::isfinite(fy))
    fail("PinholeIntrinsics", "fy", fy, "must be positive and finite");
  if (!std::isfinite(cx))
    fail("PinholeIntrinsics", "cx", cx, "must be finite");
  if (!std::isfinite(cy))
    fail("PinholeIntrinsics", "cy", cy, "must be finite");
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    fail("PinholeIntrinsics", width <= 0 || width > 16384 ? "width" : "height",
         width <= 0 || width > 16384 ? width : height, "must lie in [1, 16384]");
}

void DepthNoiseModel::validate() const {
  if (!(coefficient >= 0.f) || !std::isfinite(coefficient))
    fail("DepthNoiseModel", "coefficient", coefficient, "must be finite and >= 0");
  if (!(floor > 0.f) || !std::isfinite(floor))
    fail("DepthNoiseModel", "floor", floor, "must be positive and finite");
  if (!(systematic >= 0.f) || !std::isfinite(systematic))
    fail("DepthNoiseModel", "systematic", systematic, "must be finite and >= 0");
}

DepthImage::DepthImage(const std::vector<Eigen::Vector3f>& points,
                       const PinholeIntrinsics& intrinsics)
    : k_(intrinsics) {
  k_.validate();
  const std::size_t size = static_cast<std::size_t>(k_.width) * k_.height;
  depth_.assign(size, kEmpty);
  background_.assign(size, 0);
  for (const auto& p : points) {
    int u = 0, v = 0;
    if (!pixelOf(p, u, v))
      continue;
    float& d = depth_[static_cast<std::size_t>(v) * k_.width + u];
    d = std::min(d, p.z());
  }
}

bool DepthImage::pixelOf(const Eigen::Vector3f& p, int& u, int& v) const {
  if (!inFront(p))
    return false;
  const float fu = std::round(k_.fx * p.x() / p.z() + k_.cx);
  const float fv = std::round(k_.fy * p.y() / p.z() + k_.cy);
  if (!(fu >= 0.f && fv >= 0.f && fu < static_cast<float>(k_.width) &&
        fv < static_cast<float>(k_.height)))
    return false;
  u = static_cast<int>(fu);
  v = static_cast<int>(fv);
  return true;
}

void DepthImage::setSupportPlane(const Eigen::Vector4f& plane,
                                 const std::vector<Eigen::Vector3f>& hull) {
  const char* where = "[pcl::icf::DepthImage::setSupportPlane] ";
  if (!plane.allFinite() || std::abs(plane.head<3>().norm() - 1.f) > 1e-3f)
    throw std::invalid_argument(std::string(where) + "the plane's normal must be of unit length");
  if (hull.size() < 3)
    throw std::invalid_argument(std::string(where) + "the hull has " + std::to_string(hull.size()) +
                                " vertices, fewer than 3");
  for (const auto& vertex : hull)
    if (!vertex.allFinite())
      throw std::invalid_argument(std::string(where) + "a hull vertex is not finite");
  // The normal towards the camera (the origin): the camera lies on the plane's positive side.
  plane_ = plane[3] < 0.f ? Eigen::Vector4f(-plane) : plane;
  const Eigen::Vector3f n = plane_.head<3>();
  plane_x_ = n.unitOrthogonal();
  plane_y_ = n.cross(plane_x_);
  hull_.clear();
  for (const auto& vertex : hull)
    hull_.emplace_back(plane_x_.dot(vertex), plane_y_.dot(vertex));
  // Counter-clockwise, so that inside is left of every edge.
  float area = 0.f;
  for (std::size_t i = 0; i < hull_.size(); ++i) {
    const auto& a = hull_[i];
    const auto& b = hull_[(i + 1) % hull_.size()];
    area += a.x() * b.y() - b.x() * a.y();
  }
  if (area < 0.f)
    std::reverse(hull_.begin(), hull_.end());
}

bool DepthImage::overSupport(const Eigen::Vector3f& p) const {
  if (hull_.empty())
    return false;
  const Eigen::Vector2f q(plane_x_.dot(p), plane_y_.dot(p));
  for (std::size_t i = 0; i < hull_.size(); ++i) {
    const Eigen::Vector2f e = hull_[(i + 1) % hull_.size()] - hull_[i];
    const Eigen::Vector2f w = q - hull_[i];
    if (e.x() * w.y() - e.y() * w.x() < 0.f)
      return false;
  }
  return true;
}

void DepthImage::markBackground(const std::vector<Eigen::Vector3f>& points,
                                const pcl::Indices& indices) {
  mark(points, indices, kSupport);
}

void DepthImage::markExplained(const std::vector<Eigen::Vector3f>& points,
                               const pcl::Indices& indices) {
  mark(points, indices, kExplained);
}

void DepthImage::mark(const std::vector<Eigen::Vector3f>& points, const pcl::Indices& indices,
                      std::uint8_t kind) {
  for (const auto i : indices) {
    if (i < 0 || static_cast<std::size_t>(i) >= points.size())
      continue;
    const Eigen::Vector3f& p = points[static_cast<std::size_t>(i)];
    int u = 0, v = 0;
    if (!pixelOf(p, u, v) || depth(u, v) != p.z())
      continue;
    std::uint8_t& b = background_[static_cast<std::size_t>(v) * k_.width + u];
    if (b != kSupport)
      b = kind;
  }
}

void DepthImage::setColours(const std::vector<Eigen::Vector3f>& points,
                            const std::vector<Eigen::Vector3f>& colours) {
  if (points.size() != colours.size())
    throw std::invalid_argument("[pcl::icf::DepthImage::setColours] " +
                                std::to_string(colours.size()) + " colours for " +
                                std::to_string(points.size()) + " points");
  colour_.assign(depth_.size(), Eigen::Vector3f::Zero());
  for (std::size_t i = 0; i < points.size(); ++i) {
    int u = 0, v = 0;
    if (pixelOf(points[i], u, v) && depth(u, v) == points[i].z())
      colour_[static_cast<std::size_t>(v) * k_.width + u] = colours[i];
  }
}

PinholeIntrinsics DepthImage::fitIntrinsics(const std::vector<Eigen::Vector3f>& points, int width,
                                            int height, double& rms_pixels) {
  std::vector<std::pair<double, double>> xu, yv;
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * width + u;
      if (i >= points.size() || !inFront(points[i]))
        continue;
      xu.emplace_back(points[i].x() / points[i].z(), u);
      yv.emplace_back(points[i].y() / points[i].z(), v);
    }
  PinholeIntrinsics k;
  k.width = width;
  k.height = height;
  double sum_sq = 0.0;
  if (xu.size() < 10 || !fitLine(xu, k.fx, k.cx, sum_sq) || !fitLine(yv, k.fy, k.cy, sum_sq)) {
    rms_pixels = std::numeric_limits<double>::infinity();
    return k;
  }
  rms_pixels = std::sqrt(sum_sq / (2.0 * static_cast<double>(xu.size())));
  return k;
}

PinholeIntrinsics DepthImage::virtualCamera(const std::vector<Eigen::Vector3f>& points,
                                            float pixel_angle, int max_side) {
  float amin = 1e30f, amax = -1e30f, bmin = 1e30f, bmax = -1e30f;
  for (const auto& p : points)
    if (inFront(p)) {
      amin = std::min(amin, p.x() / p.z());
      amax = std::max(amax, p.x() / p.z());
      bmin = std::min(bmin, p.y() / p.z());
      bmax = std::max(bmax, p.y() / p.z());
    }
  PinholeIntrinsics k;
  if (amax < amin) {
    k.width = k.height = 1;
    return k;
  }
  // Tangents far off the axis (a stray point nearly beside the camera) are cut at 60 degrees.
  const float limit = 1.7320508f;
  amin = std::max(amin, -limit);
  bmin = std::max(bmin, -limit);
  amax = std::min(amax, limit);
  bmax = std::min(bmax, limit);
  float f = 1.f / std::max(pixel_angle, 1e-5f);
  const float span = std::max({amax - amin, bmax - bmin, 1e-6f});
  f = std::min(f, static_cast<float>(max_side - 3) / span);
  k.fx = k.fy = f;
  k.cx = -amin * f + 1.f;
  k.cy = -bmin * f + 1.f;
  k.width = std::max(1, static_cast<int>(std::ceil((amax - amin) * f)) + 3);
  k.height = std::max(1, static_cast<int>(std::ceil((bmax - bmin) * f)) + 3);
  return k;
}

namespace {

/** Exact nearest other point of 2D points by a uniform grid searched in growing rings. Written
 * here, not taken from PCL: the median spacing needs a few thousand queries over up to a
 * million points, and building pcl::KdTreeFLANN over them took 0.5 s of a million-point frame's
 * second (doc/HOSTILE_INPUTS.md); the grid is built in linear time. */
class NearestOtherGrid {
 public:
  explicit NearestOtherGrid(const std::vector<Eigen::Vector2f>& points) : points_(points) {
    Eigen::Vector2f hi = lo_ = points.front();
    for (const auto& p : points) {
      lo_ = lo_.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const Eigen::Vector2f extent = hi - lo_;
    const double n = static_cast<double>(points.size());
    // About one point per cell over the box; a line of points (no area) gets cells along it.
    double cell = std::sqrt(static_cast<double>(extent.x()) * extent.y() / n);
    if (!(cell > 0.0))
      cell = std::max(extent.x(), extent.y()) / n;
    if (!(cell > 0.0)) {
      cell_ = 0.0;  // every point the same: every distance 0
      return;
    }
    // At most about 4 cells per point, whatever the box's shape.
    while ((std::floor(extent.x() / cell) + 1.0) * (std::floor(extent.y() / cell) + 1.0) >
           4.0 * n + 16.0)
      cell *= 2.0;
    cell_ = cell;
    nx_ = static_cast<int>(std::floor(extent.x() / cell)) + 1;
    ny_ = static_cast<int>(std::floor(extent.y() / cell)) + 1;
    // Counting sort of the points by cell: cell c holds order_[start_[c] .. start_[c + 1]).
    start_.assign(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
    for (const auto& p : points)
      ++start_[cellIndex(cellOf(p)) + 1];
    for (std::size_t c = 1; c < start_.size(); ++c)
      start_[c] += start_[c - 1];
    order_.resize(points.size());
    std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < points.size(); ++i)
      order_[fill[cellIndex(cellOf(points[i]))]++] = i;
  }

  /** Squared distance from point \a i to the nearest other point (0 when one coincides). */
  float nearestOtherSquared(std::size_t i) const {
    if (cell_ == 0.0)
      return 0.f;
    const Eigen::Vector2f& q = points_[i];
    const Eigen::Vector2i c = cellOf(q);
    float best = std::numeric_limits<float>::infinity();
    const int rings = std::max(nx_, ny_);
    for (int r = 0; r <= rings; ++r) {
      for (int y = c.y() - r; y <= c.y() + r; ++y) {
        if (y < 0 || y >= ny_)
          continue;
        const bool edge_row = y == c.y() - r || y == c.y() + r;
        for (int x = c.x() - r; x <= c.x() + r; x += (edge_row || r == 0) ? 1 : 2 * r) {
          if (x < 0 || x >= nx_)
            continue;
          const std::size_t cell = cellIndex({x, y});
          for (std::size_t k = start_[cell]; k < start_[cell + 1]; ++k) {
            const std::size_t j = order_[k];
            if (j == i)
              continue;
            const float dx = points_[j].x() - q.x(), dy = points_[j].y() - q.y();
            best = std::min(best, dx * dx + dy * dy);
          }
        }
      }
      // The cells beyond ring r lie at least r cells away from q's; one ring more than that
      // covers a point whose cell was rounded across a border.
      const double reach = static_cast<double>(r - 1) * cell_;
      if (r >= 2 && static_cast<double>(best) <= reach * reach)
        break;
    }
    return best;
  }

 private:
  Eigen::Vector2i cellOf(const Eigen::Vector2f& p) const {
    const int x = static_cast<int>(std::floor((p.x() - lo_.x()) / cell_));
    const int y = static_cast<int>(std::floor((p.y() - lo_.y()) / cell_));
    return {std::clamp(x, 0, nx_ - 1), std::clamp(y, 0, ny_ - 1)};
  }
  std::size_t cellIndex(const Eigen::Vector2i& c) const {
    return static_cast<std::size_t>(c.y()) * static_cast<std::size_t>(nx_) +
           static_cast<std::size_t>(c.x());
  }

  const std::vector<Eigen::Vector2f>& points_;
  Eigen::Vector2f lo_;
  double cell_ = 0.0;
  int nx_ = 1, ny_ = 1;
  std::vector<std::size_t> start_, order_;
};

}  // namespace

float DepthImage::angularSpacing(const std::vector<Eigen::Vector3f>& points, std::size_t sample) {
  std::vector<Eigen::Vector2f> tangents;
  tangents.reserve(points.size());
  for (const auto& p : points)
    if (inFront(p))
      tangents.emplace_back(p.x() / p.z(), p.y() / p.z());
  if (tangents.size() < 2)
    return 0.002f;
  const NearestOtherGrid grid(tangents);
  const std::size_t stride =
      std::max<std::size_t>(1, tangents.size() / std::max<std::size_t>(1, sample));
  std::vector<float> spacing;
  for (std::size_t i = 0; i < tangents.size(); i += stride)
    if (const float sq = grid.nearestOtherSquared(i); sq > 0.f)
      spacing.push_back(std::sqrt(sq));
  if (spacing.empty())
    return 0.002f;
  std::nth_element(spacing.begin(), spacing.begin() + static_cast<long>(spacing.size() / 2),
                   spacing.end());
  return spacing[spacing.size() / 2];
}

float DepthImage::virtualPixelAngle(const std::vector<Eigen::Vector3f>& points,
                                    std::size_t sample) {
  return kVirtualPixelPitch * angularSpacing(points, sample);
}

PinholeIntrinsics DepthImage::sceneCamera(const std::vector<Eigen::Vector3f>& points, int width,
                                          int height,
                                          const std::optional<PinholeIntrinsics>& given) {
  if (given)
    return *given;
  if (width > 0) {
    double rms = std::numeric_limits<double>::infinity();
    const PinholeIntrinsics k = fitIntrinsics(points, width, height, rms);
    if (rms < 0.5)
      return k;
  }
  return virtualCamera(points, virtualPixelAngle(points));
}

}  // namespace icf
}  // namespace pcl
