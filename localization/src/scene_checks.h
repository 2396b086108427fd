/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Private to pcl_icf_localization's sources: the scene's checks before any hypothesis —
 * its depth image, a segmentation that stopped (and a camera below the table), the clusters
 * searched (the merged ones split into their convexity segments), the points other poses
 * explain taken out. */

#include <pcl/PointIndices.h>
#include <pcl/icf/localization/object_localizer.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/segmentation/tabletop_segmentation.h>
#include <pcl/icf/verification/depth_image.h>
#include <pcl_icf_internal/scene_view.h>

#include <cstddef>
#include <vector>

namespace pcl::icf::localization::detail {

/** The scene as a depth image in the camera's frame: an organized cloud's own pixel grid when
 * its points fit a pinhole (0.5 pixel), else the points projected through the given
 * intrinsics or a virtual camera (DepthImage::sceneCamera). The table's pixels are background
 * and, where \a segmentation found it with its hull, the table is the support plane. */
DepthImage sceneDepthImage(const internal::SceneView& view,
                           const segmentation::TabletopSegmentation& segmentation,
                           const LocalizerParams& params);

/** Takes the points another pose has explained (LocalizerParams::explained_indices, each an
 * index of \a view) out of every cluster; a cluster left with fewer than \a min_size points
 * is dropped. A target touching an explained neighbour is then searched on its own points,
 * not on both objects'. \throws std::invalid_argument for an index outside the scene. */
void withoutExplainedPoints(std::vector<pcl::PointIndices>& clusters,
                            const internal::SceneView& view, const pcl::Indices& explained,
                            std::size_t min_size);

/** localizeObjectsInView's outcome when the segmentation stopped (status not Ok): BadScene when the
 * data cannot be a table-top scene (empty, all NaN, too few points, millimetres) or when the
 * objects stand on the table's far side (a camera below the table), else NoClusters. */
Localization segmentationStopped(const internal::SceneView& view,
                                 segmentation::TabletopSegmentation segmentation,
                                 const LocalizerParams& params, double segmentation_ms);

/** The usable points of \a view as one cluster (LocalizerParams::segment false). */
pcl::PointIndices wholeCloud(const internal::SceneView& view);

/** What the clusters' searches run on: the clusters that look like one object, and the
 * convexity segments of those that spread wider than the model (touching objects merge into one
 * Euclidean cluster; LocalizerParams::split_merged), which are not searched whole: the votes
 * hypothesise what they hold. */
std::vector<pcl::PointIndices> searchedClusters(const internal::SceneView& view,
                                                const std::vector<pcl::PointIndices>& clusters,
                                                const IcfModel& model,
                                                const LocalizerParams& params);

}  // namespace pcl::icf::localization::detail
