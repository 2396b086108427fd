/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/segmentation/precompiled_point_types.h>
#include <pcl/point_cloud.h>
#include <pcl/types.h>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <string>

namespace pcl {
namespace icf {
namespace segmentation {

/** \brief Parameters of the table-plane stage (seeded RANSAC on a plane model). */
struct TablePlaneParams {
  /** A point is a plane inlier when its distance to the plane is < distance_threshold, in scene
   * units (metres). Must be finite and > 0. Default 0.01 (1 cm, about the Kinect's depth noise
   * at 1.5 m plus the table's unevenness). */
  double distance_threshold = 0.01;
  /** Upper bound on RANSAC hypotheses. RANSAC also stops once \a probability is reached, which
   * on a table-top scene (table = most points) takes tens of hypotheses. Must be >= 1.
   * Default 1000. */
  int max_iterations = 1000;
  /** Seed of the plane model's Mersenne twister (boost::mt19937, which is what
   * pcl::SampleConsensusModel draws samples with). Same seed, same input: same plane.
   * Default 0. */
  std::uint32_t seed = 0;
  /** The best plane is accepted (status Found) only with at least this many inliers among the
   * points given to findTablePlane. Must be >= 3. Default 500. */
  std::size_t min_inliers = 500;
  /** RANSAC's desired probability of drawing at least one outlier-free sample; sets its
   * adaptive stopping rule. Must be in (0, 1). Default 0.99. */
  double probability = 0.99;
  /** Refine the best hypothesis by a least-squares fit to its inliers (smallest principal axis of
   * their covariance, in double precision) and reselect the inliers, as pcl::SACSegmentation
   * does with setOptimizeCoefficients(true). Without it the RANSAC plane through 3 noisy points
   * can tilt enough to put a floor's far end above min_height. Default true. */
  bool refine = true;

  /** \brief Throws std::invalid_argument naming the field and its value when a field is out of
   * range. */
  void validate() const;
};

/** \brief Outcome of findTablePlane. */
enum class TablePlaneStatus {
  Found,         ///< a plane with at least min_inliers inliers
  NoPlane,       ///< fewer than 3 finite points, all points (nearly) collinear, or RANSAC failed
  TooFewInliers  ///< the best plane has fewer than min_inliers inliers (coefficients are set)
};

/** \brief "Found", "NoPlane" or "TooFewInliers". */
std::string toString(TablePlaneStatus status);

/** \brief The table plane: coefficients, inliers and outcome. */
struct TablePlane {
  TablePlaneStatus status = TablePlaneStatus::NoPlane;
  /** (a, b, c, d) with (a, b, c) a unit normal pointing to the side of the sensor origin
   * (cloud.sensor_origin_), so a*x + b*y + c*z + d is the signed height of (x, y, z) above the
   * table (positive on the sensor's side). All zero when status is NoPlane. When the sensor origin
   * lies exactly on the plane the RANSAC sign is kept. */
  Eigen::Vector4f coefficients = Eigen::Vector4f::Zero();
  /** Indices (into the cloud given to findTablePlane) of the points within distance_threshold
   * of the plane, in the order of the given indices (increasing for finiteIndices). */
  pcl::Indices inliers;
  /** RANSAC hypotheses drawn. */
  int iterations = 0;

  /** \brief status == Found. */
  bool found() const { return status == TablePlaneStatus::Found; }
};

/** \brief The dominant plane of \a cloud[indices], by RANSAC with a plane model, seeded so that
 * the result is deterministic.
 *
 * Determinism: pcl::SACSegmentation seeds its model's generator with the fixed 12345 (or the
 * clock) and offers no seed; here a pcl::SampleConsensusModelPlane subclass reseeds the model's
 * protected boost::mt19937 (`rng_alg_`, which draws the samples) with \a params.seed, and
 * pcl::RandomSampleConsensus runs single-threaded (its default), so the hypotheses do not depend
 * on scheduling. RANSAC stops at \a params.max_iterations or when its adaptive bound for
 * \a params.probability is met (5-10 hypotheses on the real scenes). Re-entrant: the model and
 * its generator live in the call.
 *
 * \param[in] cloud  read only during the call; its sensor_origin_ orients the normal.
 * \param[in] indices  the candidate points; each must be < cloud.size(); non-finite points
 *            among them are ignored.
 * \param[in] params  see TablePlaneParams.
 * \return the plane; status NoPlane with fewer than 3 usable points, collinear/coincident points
 *         or when RANSAC finds no model; TooFewInliers when the best plane has fewer than
 *         params.min_inliers inliers. Never throws for data outcomes.
 * \throws std::invalid_argument when \a params is invalid or an index is out of range.
 *
 * \code
 * const auto finite = pcl::icf::segmentation::finiteIndices(scene);
 * const auto plane = pcl::icf::segmentation::findTablePlane(scene, finite, {});
 * if (plane.found()) { ... plane.coefficients, plane.inliers ... }
 * \endcode
 */
template <typename PointT>
TablePlane findTablePlane(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices,
                          const TablePlaneParams& params);

/** \brief \a plane carried to \a cloud[indices]: its inliers there, one least-squares refit on
 * them (when params.refine) and the inliers of the refitted plane.
 *
 * Used after findTablePlane on a voxel-downsampled copy, so that the plane and its inliers are
 * those of the full-resolution cloud. The status and iterations of \a plane are kept (the
 * acceptance test min_inliers was made where the plane was searched); a NoPlane plane comes back
 * with no inliers.
 * \throws std::invalid_argument when \a params is invalid or an index is out of range.
 */
template <typename PointT>
TablePlane refineTablePlane(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices,
                            const TablePlane& plane, const TablePlaneParams& params);

/** \brief Indices among \a indices of the finite points whose distance to the plane
 * \a coefficients (unit normal) is < \a distance_threshold, increasing when \a indices is.
 *
 * Used to carry a plane found on a downsampled cloud back to the full-resolution cloud.
 * \throws std::invalid_argument when an index is out of range or distance_threshold <= 0.
 */
template <typename PointT>
pcl::Indices planeInliers(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices,
                          const Eigen::Vector4f& coefficients, double distance_threshold);

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl

// The templates above are compiled into pcl_icf_segmentation for
// PCL_ICF_SEGMENTATION_POINT_TYPES (precompiled_point_types.h: other point types, how); their
// bodies are in the library's sources (src/impl/table_plane.hpp), not installed.
