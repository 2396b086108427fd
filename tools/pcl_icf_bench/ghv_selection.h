/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief The peer of localizeObjects's selection: PCL's Global Hypotheses Verification
 * (Aldoma et al. 2012, pcl::GlobalHypothesesVerification) choosing among the same judged
 * hypotheses which objects are in the frame (pcl_icf_bench --bop --selection ghv). Not
 * deterministic: PCL 1.13's GHV shuffles its annealing moves with std::random_device, which no
 * seed reaches; the bench's figures are over several runs. */

#include <pcl/icf/localization/objects_localizer.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstddef>
#include <vector>

namespace pcl_icf_bench {

/** \brief GHV's settings: the values of PCL's global hypothesis verification tutorial (its
 * authors' for Kinect-like scenes, metres), and how many hypotheses of each object it is given. */
struct GhvParams {
  std::size_t per_object = 5;  ///< each object's best judged hypotheses by score
  float resolution = 0.005f;   ///< the scene's and the models' voxel grid
  float inlier_threshold = 0.005f;
  float occlusion_threshold = 0.01f;
  float clutter_radius = 0.04f;
  float regularizer = 3.f;
  float clutter_regularizer = 5.f;
  std::size_t model_points = 4000;  ///< points sampled on each model's surface
};

/** \brief Each object's hypotheses (indices into found.objects[k].clusters) that GHV keeps,
 * best score first, at most queries[k].max_instances. The scene GHV explains is the part above
 * the table when there is one (else every finite point), the occlusion cloud the whole frame. */
std::vector<std::vector<int>> ghvSelect(
    const pcl::PointCloud<pcl::PointXYZRGBA>& scene,
    const pcl::icf::localization::ObjectsLocalization& found,
    const std::vector<pcl::icf::localization::ObjectQuery>& queries, const GhvParams& params = {});

}  // namespace pcl_icf_bench
