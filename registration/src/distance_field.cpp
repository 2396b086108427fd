/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/registration/distance_field.h>
#include <pcl_icf_internal/parameter_check.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

// The lookups below run hundreds of thousands of times per search: inlined into distance() and
// closestPoint() instead of three calls per lookup.
#define PCL_ICF_FIELD_INLINE __attribute__((always_inline)) inline

namespace pcl {
namespace icf {

void DistanceFieldParams::validate() const {
  const internal::ParameterCheck fail("DistanceFieldParams");
  if (!(margin >= 0.f) || !std::isfinite(margin))
    fail("margin", margin, "must be finite and >= 0");
  if (!(cell_size >= 0.f) || !std::isfinite(cell_size))
    fail("cell_size", cell_size, "must be finite and >= 0 (0 = automatic)");
  if (cell_size == 0.f && (resolution < 2 || resolution > 4096))
    fail("resolution", resolution, "must lie in [2, 4096]");
  if (max_nodes < 8)
    fail("max_nodes", static_cast<double>(max_nodes), "must be at least 8");
  if (threads < 0)
    fail("threads", threads, "must be >= 0 (0 = all cores)");
}

ClosestPointField::ClosestPointField(const ClosestFaceQuery& index,
                                     const DistanceFieldParams& params) {
  params.validate();
  const FaceMesh& mesh = index.mesh();
  const Eigen::Vector3f lo = mesh.boundsMin() - Eigen::Vector3f::Constant(params.margin);
  const Eigen::Vector3f hi = mesh.boundsMax() + Eigen::Vector3f::Constant(params.margin);
  const Eigen::Vector3f extent = (hi - lo).cwiseMax(1e-6f);
  cell_ = params.cell_size > 0.f ? params.cell_size
                                 : extent.maxCoeff() / static_cast<float>(params.resolution);
  if (!(cell_ > 0.f) || !std::isfinite(cell_))
    throw std::invalid_argument("ClosestPointField: mesh extent gives no usable cell size");
  inv_cell_ = 1.f / cell_;
  double nodes = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double n = std::ceil(extent[a] / cell_) + 1.0;
    nodes *= n;
    if (nodes > static_cast<double>(params.max_nodes)) {
      std::ostringstream msg;
      msg << "ClosestPointField: a grid of cell " << cell_ << " over an extent of "
          << extent.transpose() << " needs more than max_nodes = " << params.max_nodes
          << " nodes; raise cell_size or max_nodes";
      throw std::invalid_argument(msg.str());
    }
    dims_[a] = static_cast<int>(n);
  }
  origin_ = lo;
  nodes_.resize(nodeCount() * 3);
  distances_.resize(nodeCount());
  medial_.assign(nodeCount(), 0);

  const int threads = params.threads;
  // Rows along x are filled in order; each node's exact query is bounded by the previous
  // node's distance plus one cell (the distance is 1-Lipschitz), which keeps Embree's
  // traversal short. The stored values do not depend on the bound or the thread count.
  const int rows = dims_.y() * dims_.z();
#pragma omp parallel for schedule(dynamic, 4) \
    num_threads(threads > 0 ? threads : omp_get_num_procs())
  for (int row = 0; row < rows; ++row) {
    const int y = row % dims_.y(), z = row / dims_.y();
    float previous = std::numeric_limits<float>::infinity();
    for (int x = 0; x < dims_.x(); ++x) {
      const Eigen::Vector3f position = origin_ + cell_ * Eigen::Vector3f(x, y, z);
      ClosestFace c = index.closestFace(position, previous + 1.01f * cell_);
      if (!c.found())
        c = index.closestFace(position);
      previous = c.distance;
      const std::size_t node = static_cast<std::size_t>(row) * dims_.x() + x;
      distances_[node] = c.distance;
      const std::size_t i = 3 * node;
      nodes_[i] = c.point.x();
      nodes_[i + 1] = c.point.y();
      nodes_[i + 2] = c.point.z();
    }
  }
  flagMedialCells();
}

void ClosestPointField::flagMedialCells() {
  // Where the closest point is continuous it moves at most about one cell diagonal between
  // neighbouring nodes (the projection on a convex patch is non-expansive). 1.25 times that marks
  // a jump: the cell straddles a medial axis.
  const float limit = 1.25f * 1.7320508f * cell_;
  const std::size_t sy = static_cast<std::size_t>(dims_.x());
  const std::size_t sz = sy * static_cast<std::size_t>(dims_.y());
  const std::size_t corners[7] = {1, sy, sy + 1, sz, sz + 1, sz + sy, sz + sy + 1};
  for (int z = 0; z + 1 < dims_.z(); ++z)
    for (int y = 0; y + 1 < dims_.y(); ++y)
      for (int x = 0; x + 1 < dims_.x(); ++x) {
        const std::size_t base = x + y * sy + z * sz;
        const Eigen::Map<const Eigen::Vector3f> c0(&nodes_[3 * base]);
        for (std::size_t k : corners)
          if ((Eigen::Map<const Eigen::Vector3f>(&nodes_[3 * (base + k)]) - c0).norm() > limit) {
            medial_[base] = 1;
            break;
          }
      }
}

double ClosestPointField::medialCellRatio() const {
  std::size_t flagged = 0;
  for (std::uint8_t m : medial_)
    flagged += m;
  const double cells = static_cast<double>(dims_.x() - 1) * (dims_.y() - 1) * (dims_.z() - 1);
  return cells > 0 ? static_cast<double>(flagged) / cells : 0.0;
}

namespace {
/** A grid coordinate clamped to [0, \a nodes - 1]; NaN to 0. */
PCL_ICF_FIELD_INLINE float clampToGrid(float g, int nodes) {
  return g > 0.f ? std::min(g, static_cast<float>(nodes - 1)) : 0.f;
}
}  // namespace

PCL_ICF_FIELD_INLINE ClosestPointField::Cell ClosestPointField::locate(
    const Eigen::Vector3f& p) const {
  // Grid coordinates, clamped so that the 8 nodes of the cell exist.
  const Eigen::Vector3f g = (p - origin_) * inv_cell_;
  Cell cell;
  for (int a = 0; a < 3; ++a) {
    const float ga = clampToGrid(g[a], dims_[a]);
    int ia = static_cast<int>(ga);
    if (ia >= dims_[a] - 1)
      ia = dims_[a] - 2;
    cell.i[a] = ia;
    cell.t[a] = ga - static_cast<float>(ia);
  }
  cell.base = static_cast<std::size_t>(cell.i[0]) +
              static_cast<std::size_t>(dims_.x()) *
                  (static_cast<std::size_t>(cell.i[1]) +
                   static_cast<std::size_t>(dims_.y()) * static_cast<std::size_t>(cell.i[2]));
  return cell;
}

PCL_ICF_FIELD_INLINE Eigen::Vector3f ClosestPointField::interpolateClosest(const Cell& cell) const {
  const std::size_t sx = 3, sy = 3 * static_cast<std::size_t>(dims_.x()),
                    sz = sy * static_cast<std::size_t>(dims_.y());
  const float* n = nodes_.data() + 3 * cell.base;
  const float* t = cell.t;
  Eigen::Vector3f out;
  for (int c = 0; c < 3; ++c) {
    const float c00 = n[c] + t[0] * (n[sx + c] - n[c]);
    const float c10 = n[sy + c] + t[0] * (n[sy + sx + c] - n[sy + c]);
    const float c01 = n[sz + c] + t[0] * (n[sz + sx + c] - n[sz + c]);
    const float c11 = n[sz + sy + c] + t[0] * (n[sz + sy + sx + c] - n[sz + sy + c]);
    const float c0 = c00 + t[1] * (c10 - c00);
    const float c1 = c01 + t[1] * (c11 - c01);
    out[c] = c0 + t[2] * (c1 - c0);
  }
  return out;
}

PCL_ICF_FIELD_INLINE float ClosestPointField::interpolateDistance(const Cell& cell) const {
  const std::size_t sy = static_cast<std::size_t>(dims_.x()),
                    sz = sy * static_cast<std::size_t>(dims_.y());
  const float* d = distances_.data() + cell.base;
  const float* t = cell.t;
  const float c00 = d[0] + t[0] * (d[1] - d[0]);
  const float c10 = d[sy] + t[0] * (d[sy + 1] - d[sy]);
  const float c01 = d[sz] + t[0] * (d[sz + 1] - d[sz]);
  const float c11 = d[sz + sy] + t[0] * (d[sz + sy + 1] - d[sz + sy]);
  const float c0 = c00 + t[1] * (c10 - c00);
  const float c1 = c01 + t[1] * (c11 - c01);
  return c0 + t[2] * (c1 - c0);
}

float ClosestPointField::distanceUpperBound(const Eigen::Vector3f& p) const {
  if (!p.allFinite())
    return std::numeric_limits<float>::infinity();
  const Eigen::Vector3f g = (p - origin_) * inv_cell_;
  std::size_t node = 0, stride = 1;
  for (int a = 0; a < 3; ++a) {
    const float ga = clampToGrid(g[a], dims_[a]);
    const int ia = std::min(static_cast<int>(ga + 0.5f), dims_[a] - 1);  // the nearest node
    node += stride * static_cast<std::size_t>(ia);
    stride *= static_cast<std::size_t>(dims_[a]);
  }
  const float d = (p - Eigen::Map<const Eigen::Vector3f>(&nodes_[3 * node])).norm();
  // The stored point and the exact query's distance are float roundings of closest-point
  // computations on faces within the grid (errors of a few float epsilons, 6e-8, of the
  // coordinates involved): widen by 1e-5 of the largest of them.
  const float scale = p.cwiseAbs().maxCoeff() + origin_.cwiseAbs().maxCoeff() +
                      cell_ * static_cast<float>(dims_.maxCoeff());
  return d + 1e-5f * (d + scale);
}

Eigen::Vector3f ClosestPointField::closestPoint(const Eigen::Vector3f& p) const {
  return interpolateClosest(locate(p));
}

float ClosestPointField::distance(const Eigen::Vector3f& p) const {
  const Cell cell = locate(p);
  if (medial_[cell.base]) {
    // Beyond the grid the clamped trilinear distance would understate: add the overshoot.
    const Eigen::Vector3f g =
        origin_ + cell_ * Eigen::Vector3f(cell.i[0] + cell.t[0], cell.i[1] + cell.t[1],
                                          cell.i[2] + cell.t[2]);
    return interpolateDistance(cell) + (p - g).norm();
  }
  return (p - interpolateClosest(cell)).norm();
}

}  // namespace icf
}  // namespace pcl
