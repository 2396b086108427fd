/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/segmentation/tabletop_segmentation.h>
#include <pcl_icf_internal/parameter_check.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace pcl {
namespace icf {
namespace segmentation {
namespace {

/** Throws std::invalid_argument "[pcl::icf::segmentation::<owner>::validate] <field> = <value>:
 * <requirement>" (internal::ParameterCheck). */
template <typename T>
[[noreturn]] void fail(const char* owner, const std::string& field, const T& value,
                       const char* requirement) {
  const internal::ParameterCheck check(std::string("segmentation::") + owner);
  check(field, value, requirement);
}

void validateVoxel(const VoxelParams& p, const char* owner, const std::string& prefix) {
  if (!std::isfinite(p.voxel_size) || p.voxel_size < 0.0)
    fail(owner, prefix + "voxel_size", p.voxel_size, "must be finite and >= 0 (0 = off)");
}

void validatePlane(const TablePlaneParams& p, const char* owner, const std::string& prefix) {
  if (!std::isfinite(p.distance_threshold) || p.distance_threshold <= 0.0)
    fail(owner, prefix + "distance_threshold", p.distance_threshold, "must be finite and > 0");
  if (p.max_iterations < 1)
    fail(owner, prefix + "max_iterations", p.max_iterations, "must be >= 1");
  if (p.min_inliers < 3)
    fail(owner, prefix + "min_inliers", p.min_inliers, "must be >= 3");
  if (!(p.probability > 0.0 && p.probability < 1.0))
    fail(owner, prefix + "probability", p.probability, "must be in (0, 1)");
}

void validateAbove(const AboveTableParams& p, const char* owner, const std::string& prefix) {
  if (!std::isfinite(p.min_height))
    fail(owner, prefix + "min_height", p.min_height, "must be finite");
  if (!std::isfinite(p.max_height))
    fail(owner, prefix + "max_height", p.max_height, "must be finite");
  if (!(p.min_height < p.max_height)) {
    std::ostringstream req;
    req << "must be < min_height = " << p.min_height;
    fail(owner, prefix + "max_height", p.max_height, req.str().c_str());
  }
}

void validateCluster(const ClusterParams& p, const char* owner, const std::string& prefix) {
  if (!std::isfinite(p.tolerance) || p.tolerance <= 0.0)
    fail(owner, prefix + "tolerance", p.tolerance, "must be finite and > 0");
  if (p.min_size < 1)
    fail(owner, prefix + "min_size", p.min_size, "must be >= 1");
  if (p.max_size < p.min_size) {
    std::ostringstream req;
    req << "must be >= min_size = " << p.min_size;
    fail(owner, prefix + "max_size", p.max_size, req.str().c_str());
  }
  if (p.max_size > std::numeric_limits<pcl::uindex_t>::max())
    fail(owner, prefix + "max_size", p.max_size, "must fit pcl::uindex_t");
  if (p.method != ClusterMethod::Grid && p.method != ClusterMethod::PclKdTree &&
      p.method != ClusterMethod::PclOrganized)
    fail(owner, prefix + "method", static_cast<int>(p.method), "is not a ClusterMethod value");
}

}  // namespace

void VoxelParams::validate() const {
  validateVoxel(*this, "VoxelParams", "");
}

void TablePlaneParams::validate() const {
  validatePlane(*this, "TablePlaneParams", "");
}

void AboveTableParams::validate() const {
  validateAbove(*this, "AboveTableParams", "");
}

void ClusterParams::validate() const {
  validateCluster(*this, "ClusterParams", "");
}

void TabletopParams::validate() const {
  validateVoxel(voxel, "TabletopParams", "voxel.");
  validatePlane(plane, "TabletopParams", "plane.");
  validateAbove(above_table, "TabletopParams", "above_table.");
  validateCluster(cluster, "TabletopParams", "cluster.");
  if (!std::isfinite(max_scene_extent) || max_scene_extent < 0.0)
    fail("TabletopParams", "max_scene_extent", max_scene_extent,
         "must be finite and >= 0 (0 = off)");
  if (!std::isfinite(max_pixel_spacing_factor) || max_pixel_spacing_factor < 0.0)
    fail("TabletopParams", "max_pixel_spacing_factor", max_pixel_spacing_factor,
         "must be finite and >= 0 (0 = off)");
}

std::string toString(TablePlaneStatus status) {
  switch (status) {
    case TablePlaneStatus::Found:
      return "Found";
    case TablePlaneStatus::NoPlane:
      return "NoPlane";
    case TablePlaneStatus::TooFewInliers:
      return "TooFewInliers";
  }
  return "unknown TablePlaneStatus";
}

std::string toString(AboveTableStatus status) {
  switch (status) {
    case AboveTableStatus::Ok:
      return "Ok";
    case AboveTableStatus::NoPlane:
      return "NoPlane";
    case AboveTableStatus::DegenerateHull:
      return "DegenerateHull";
  }
  return "unknown AboveTableStatus";
}

std::string toString(ClusterMethod method) {
  switch (method) {
    case ClusterMethod::Grid:
      return "Grid";
    case ClusterMethod::PclKdTree:
      return "PclKdTree";
    case ClusterMethod::PclOrganized:
      return "PclOrganized";
  }
  return "unknown ClusterMethod";
}

std::string toString(TabletopStatus status) {
  switch (status) {
    case TabletopStatus::Ok:
      return "Ok";
    case TabletopStatus::EmptyCloud:
      return "EmptyCloud";
    case TabletopStatus::NoFinitePoints:
      return "NoFinitePoints";
    case TabletopStatus::TooFewPoints:
      return "TooFewPoints";
    case TabletopStatus::SceneUnitsSuspect:
      return "SceneUnitsSuspect";
    case TabletopStatus::NoPlane:
      return "NoPlane";
    case TabletopStatus::NoCluster:
      return "NoCluster";
  }
  return "unknown TabletopStatus";
}

void sortClusters(std::vector<pcl::PointIndices>& clusters) {
  for (pcl::PointIndices& c : clusters)
    std::sort(c.indices.begin(), c.indices.end());
  std::sort(clusters.begin(), clusters.end(),
            [](const pcl::PointIndices& a, const pcl::PointIndices& b) {
              if (a.indices.size() != b.indices.size())
                return a.indices.size() > b.indices.size();
              if (a.indices.empty())
                return false;
              return a.indices.front() < b.indices.front();
            });
}

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl
