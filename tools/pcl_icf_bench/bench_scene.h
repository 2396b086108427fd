/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// pcl_icf_bench's scene-level methods (icf-scene, icf-objects): the whole localizer on the
// whole scene, segmentation included, instead of one registration on a given cluster.
#pragma once

#include "bench_manifest.h"
#include "bench_methods.h"

#include <pcl/icf/localization/object_localizer.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstddef>
#include <vector>

namespace pcl_icf_tools {
namespace bench {

/** A case's whole scene as read, the camera set (the manifest's camera=, else the file's
 * VIEWPOINT): exactly one of the clouds is set, rgba when the file has colour. */
struct SceneInput {
  pcl::PointCloud<pcl::PointXYZRGBA>::Ptr rgba;
  CloudXYZ::Ptr xyz;
  std::size_t finite_points = 0;
};

/** Reads the case's scene (any of pcl::icf::io::loadSceneCloud's formats); BadInput naming
 * the case when it cannot be read or holds no finite point. */
SceneInput loadScene(const CaseSpec& c);

/** pcl::icf::localization::localizeObject on the whole scene; the time is the whole call.
 * converged: the status is Found; the pose: the best accepted cluster's (identity otherwise);
 * detail: the status, the clusters tried and the best one's score, or why the best-scoring
 * cluster was rejected. */
MethodRun runScene(const SceneInput& scene, const PreparedModel& model,
                   const pcl::icf::localization::LocalizerParams& params);

/** pcl::icf::localization::localizeObjects on the whole scene with \a model and \a others (every
 * other model of the manifest) in one call, each object's instances competing for the scene's
 * points; the time is the whole call, the rest as runScene for \a model's result. */
MethodRun runSceneWithOthers(const SceneInput& scene, const PreparedModel& model,
                             const std::vector<const PreparedModel*>& others,
                             const pcl::icf::localization::LocalizerParams& params);

}  // namespace bench
}  // namespace pcl_icf_tools
