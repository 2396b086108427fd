/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/registration/closest_face_query.h>

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <vector>

namespace pcl {
namespace icf {

/** \brief Parameters of ClosestPointField. Lengths in mesh units (metres by default). */
struct DistanceFieldParams {
  /** Space around the mesh's bounding box covered by the grid. Beyond it the field still
   * answers (the query is clamped to the grid) with a distance that is at least the margin,
   * so anything that only needs to know "farther than margin" stays exact. The default covers
   * the thesis objective's support: f(d) = 0 for d > 50 mm. */
  float margin = 0.06f;
  /** Grid step. 0 picks (longest side of the grid) / resolution. */
  float cell_size = 0.f;
  /** Cells along the longest side when cell_size is 0. */
  int resolution = 96;
  /** Refuse to allocate more nodes than this (12 bytes each). */
  std::size_t max_nodes = std::size_t(1) << 25;
  /** Threads used to build (0: all cores). The content does not depend on it. */
  int threads = 0;

  /** \throws std::invalid_argument naming the field and value when a parameter is absurd. */
  void validate() const;
};

/** \brief A precomputed closest-point field over a mesh's bounding box plus a margin, for
 * scoring millions of poses (doc/icf.md section 3).
 *
 * Every grid node stores the exact closest point on the mesh (from a ClosestFaceQuery). A
 * lookup interpolates the closest point trilinearly and returns |p - c~|. Near a planar patch
 * the closest point is an affine function of p, so the interpolation is exact there and the
 * distance keeps its true kink at the surface (an unsigned distance grid rounds it off: about
 * 1.35 mm at 2.7 mm cells). The error is confined to cells that straddle an edge or a medial
 * axis; test/registration/distance_field_test.cpp measures it against the exact distance
 * (bound: errorBound()).
 *
 * Immutable after construction; lookups are const and thread-safe. Does not keep a reference
 * to the mesh or the index. */
struct ModelFileAccess;  // model_file.cpp: writes and reads the prepared field

class ClosestPointField {
 public:
  using Ptr = std::shared_ptr<ClosestPointField>;
  using ConstPtr = std::shared_ptr<const ClosestPointField>;

  /** \throws std::invalid_argument for absurd parameters or a grid above max_nodes. */
  ClosestPointField(const ClosestFaceQuery& index, const DistanceFieldParams& params = {});

  /** \brief Approximate distance from \a p to the mesh (exact on planar patches): |p - c~|
   * in cells where the closest point is continuous, the trilinear distance in cells that
   * straddle a medial axis (where interpolating closest points from opposite sides would put
   * c~ in mid-air). */
  float distance(const Eigen::Vector3f& p) const;

  /** \brief Interpolated closest point on the mesh to \a p. Meaningful where the closest
   * point is continuous (near the surface, on its convex side); across a medial axis it is a
   * blend of points on different faces. */
  Eigen::Vector3f closestPoint(const Eigen::Vector3f& p) const;

  /** \brief A strict upper bound on the exact distance from \a p to the mesh, anywhere: |p - c|
   * for the closest point c (on the mesh, exact) stored at the grid node nearest to \a p
   * (clamped to the grid), widened beyond float rounding. Inside the grid at most the exact
   * distance plus twice the distance to that node (at most sqrt(3) cells). Infinite for a
   * non-finite \a p. */
  float distanceUpperBound(const Eigen::Vector3f& p) const;

  float cellSize() const { return cell_; }
  const Eigen::Vector3f& origin() const { return origin_; }
  const Eigen::Vector3i& dimensions() const { return dims_; }
  std::size_t nodeCount() const { return static_cast<std::size_t>(dims_.prod()); }
  /** \brief Bound on |distance(p) - exact(p)| for p inside the grid: one cell. The error is 0
   * to rounding above flat patches; the largest errors, in medial-axis cells, stay below it
   * (test/registration/distance_field_test.cpp). */
  float errorBound() const { return cell_; }
  /** \brief Share of cells that straddle a medial axis (answered by trilinear distance). */
  double medialCellRatio() const;

 private:
  struct Cell {
    int i[3];
    float t[3];
    std::size_t base;  // node index of the cell's lowest corner
  };
  Cell locate(const Eigen::Vector3f& p) const;
  void flagMedialCells();
  Eigen::Vector3f interpolateClosest(const Cell& c) const;
  float interpolateDistance(const Cell& c) const;
  friend struct ModelFileAccess;
  ClosestPointField() = default;

  Eigen::Vector3f origin_ = Eigen::Vector3f::Zero();
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();  // nodes per axis
  float cell_ = 0.f, inv_cell_ = 0.f;
  std::vector<float> nodes_;          // closest points, xyz interleaved, x fastest
  std::vector<float> distances_;      // exact distance at each node
  std::vector<std::uint8_t> medial_;  // per cell (indexed by its lowest node): 1 = straddles
};

}  // namespace icf
}  // namespace pcl
