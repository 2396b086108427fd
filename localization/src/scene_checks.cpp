/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "scene_checks.h"

#include <pcl/icf/registration/global_search.h>
#include <pcl/icf/registration/usable_point.h>
#include <pcl/icf/segmentation/convexity_split.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>

namespace pcl::icf::localization::detail {

using internal::SceneView;

namespace {

/** The points of \a cluster not in \a explained, sorted. */
pcl::PointIndices unexplainedPoints(const pcl::PointIndices& cluster,
                                    const pcl::Indices& explained) {
  pcl::Indices all = cluster.indices, some = explained;
  std::sort(all.begin(), all.end());
  std::sort(some.begin(), some.end());
  pcl::PointIndices rest;
  std::set_difference(all.begin(), all.end(), some.begin(), some.end(),
                      std::back_inserter(rest.indices));
  return rest;
}

/** Points at object heights (above_table.min_height to max_height) on the table's far side
 * from the camera and over the table (inside its inliers' extent on the plane, shrunk by a
 * tenth): an opaque table top hides them from a camera above it, so many of them, and nothing
 * on the camera's side, is a camera placed below the table. */
std::size_t pointsBeyondTheTable(const SceneView& view,
                                 const segmentation::TabletopSegmentation& segmentation,
                                 const LocalizerParams& params) {
  const Eigen::Vector4f& plane = segmentation.plane.coefficients;
  const Eigen::Vector3f n = plane.head<3>();
  if (n.isZero(0.f) || segmentation.plane.inliers.empty())
    return 0;
  const Eigen::Vector3f e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  Eigen::Vector2f lo = Eigen::Vector2f::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (const auto i : segmentation.plane.inliers) {
    const Eigen::Vector3f& p = view.points[static_cast<std::size_t>(i)];
    const Eigen::Vector2f q(e1.dot(p), e2.dot(p));
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  const Eigen::Vector2f margin = 0.1f * (hi - lo);
  lo += margin;
  hi -= margin;
  const auto& heights = params.tuning().segmentation.above_table;
  std::size_t beyond = 0;
  for (const auto& p : view.points) {
    if (!isUsablePoint(p))
      continue;
    const double depth = -(n.dot(p) + plane[3]);
    const Eigen::Vector2f q(e1.dot(p), e2.dot(p));
    beyond += depth > heights.min_height && depth < heights.max_height &&
              (q.array() >= lo.array()).all() && (q.array() <= hi.array()).all();
  }
  return beyond;
}

/** The global search's merged-cluster test (spreadsWiderThanModel) on one cluster; clusters
 * of fewer than 10 points count as single. */
bool clusterLooksMerged(const SceneView& view, const pcl::PointIndices& cluster,
                        const IcfModel& model, const LocalizerParams& params) {
  if (cluster.indices.size() < 10)
    return false;
  std::vector<Eigen::Vector3f> points;
  points.reserve(cluster.indices.size());
  for (const auto i : cluster.indices)
    points.push_back(view.points[static_cast<std::size_t>(i)]);
  return spreadsWiderThanModel(points, model.radius(), params.tuning().icf.tuning().global);
}

pcl::PointCloud<pcl::PointXYZRGBA> colouredCloud(const SceneView& view) {
  pcl::PointCloud<pcl::PointXYZRGBA> cloud;
  cloud.resize(view.points.size());
  for (std::size_t i = 0; i < view.points.size(); ++i) {
    cloud[i].getVector3fMap() = view.points[i];
    if (!view.colours.empty()) {
      const Eigen::Vector3f c = 255.f * view.colours[i];
      cloud[i].r = static_cast<std::uint8_t>(c.x());
      cloud[i].g = static_cast<std::uint8_t>(c.y());
      cloud[i].b = static_cast<std::uint8_t>(c.z());
    }
  }
  return cloud;
}

}  // namespace

/** The scene as a depth image in the camera's frame: an organized cloud's own pixel grid when
 * its points fit a pinhole (0.5 pixel), else the points projected through the given
 * intrinsics or a virtual camera (DepthImage::sceneCamera). The table's pixels are background. */
DepthImage sceneDepthImage(const SceneView& view,
                           const segmentation::TabletopSegmentation& segmentation,
                           const LocalizerParams& params) {
  DepthImage image(view.points, DepthImage::sceneCamera(view.points, view.width, view.height,
                                                        params.intrinsics));
  image.markBackground(view.points, segmentation.plane.inliers);
  if (segmentation.plane.found() && segmentation.hull.size() >= 3)
    image.setSupportPlane(segmentation.plane.coefficients, segmentation.hull);
  image.markExplained(view.points, params.explained_indices);
  if (!view.colours.empty())
    image.setColours(view.points, view.colours);
  return image;
}

/** Takes the points another pose has explained (LocalizerParams::explained_indices, each an
 * index of \a view) out of every cluster; a cluster left with fewer than \a min_size points
 * is dropped. A target touching an explained neighbour is then searched on its own points,
 * not on both objects'. \throws std::invalid_argument for an index outside the scene. */
void withoutExplainedPoints(std::vector<pcl::PointIndices>& clusters, const SceneView& view,
                            const pcl::Indices& explained, std::size_t min_size) {
  for (const int i : explained)
    if (i < 0 || static_cast<std::size_t>(i) >= view.points.size())
      throw std::invalid_argument(
          "[pcl::icf::localization::localizeObject] LocalizerParams::explained_indices: index " +
          std::to_string(i) + " is outside the scene's " + std::to_string(view.points.size()) +
          " points");
  if (explained.empty())
    return;
  std::vector<pcl::PointIndices> kept;
  for (const auto& cluster : clusters) {
    pcl::PointIndices rest = unexplainedPoints(cluster, explained);
    if (rest.indices.size() >= min_size)
      kept.push_back(std::move(rest));
  }
  clusters = std::move(kept);
}

/** localizeObjectsInView's outcome when the segmentation stopped (status not Ok): BadScene when the
 * data cannot be a table-top scene (empty, all NaN, too few points, millimetres) or when the
 * objects stand on the table's far side (a camera below the table), else NoClusters. */
Localization segmentationStopped(const SceneView& view,
                                 segmentation::TabletopSegmentation segmentation,
                                 const LocalizerParams& params, double segmentation_ms) {
  Localization out;
  out.segmentation_ms = segmentation_ms;
  const segmentation::TabletopStatus status = segmentation.status;
  const bool bad = status == segmentation::TabletopStatus::EmptyCloud ||
                   status == segmentation::TabletopStatus::NoFinitePoints ||
                   status == segmentation::TabletopStatus::TooFewPoints ||
                   status == segmentation::TabletopStatus::SceneUnitsSuspect;
  out.status = bad ? LocalizationStatus::BadScene : LocalizationStatus::NoClusters;
  out.message =
      toString(status) + (segmentation.message.empty() ? "" : ": " + segmentation.message);
  if (status == segmentation::TabletopStatus::NoCluster) {
    const std::size_t beyond = pointsBeyondTheTable(view, segmentation, params);
    if (beyond >= params.cluster.min_size) {
      out.status = LocalizationStatus::BadScene;
      out.message =
          "the camera is on the wrong side of the table: nothing stands on its "
          "side, " +
          std::to_string(beyond) +
          " points stand on the other (check the camera pose: --camera, or the "
          "cloud's VIEWPOINT)";
    }
  }
  out.segmentation = std::move(segmentation);
  out.total_ms = segmentation_ms;
  return out;
}

/** The usable points of \a view as one cluster (LocalizerParams::segment false). */
pcl::PointIndices wholeCloud(const SceneView& view) {
  pcl::PointIndices all;
  for (std::size_t i = 0; i < view.points.size(); ++i)
    if (isUsablePoint(view.points[i]))
      all.indices.push_back(static_cast<pcl::index_t>(i));
  return all;
}

/** What the clusters' searches run on: the clusters that look like one object, and the
 * convexity segments of those that spread wider than the model (touching objects merge into one
 * Euclidean cluster; LocalizerParams::split_merged), which are not searched whole: the votes
 * hypothesise what they hold. */
std::vector<pcl::PointIndices> searchedClusters(const SceneView& view,
                                                const std::vector<pcl::PointIndices>& clusters,
                                                const IcfModel& model,
                                                const LocalizerParams& params) {
  std::vector<pcl::PointIndices> searched, segments;
  pcl::PointCloud<pcl::PointXYZRGBA> coloured;
  for (const auto& cluster : clusters) {
    if (!clusterLooksMerged(view, cluster, model, params)) {
      searched.push_back(cluster);
      continue;
    }
    if (!params.split_merged)
      continue;
    if (coloured.empty())
      coloured = colouredCloud(view);
    for (auto& segment : segmentation::splitByConvexity(coloured, cluster, params.tuning().split))
      if (segment.indices.size() < cluster.indices.size())
        segments.push_back(std::move(segment));
  }
  searched.insert(searched.end(), segments.begin(), segments.end());
  return searched;
}

}  // namespace pcl::icf::localization::detail
