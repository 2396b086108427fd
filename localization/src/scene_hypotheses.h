/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Private to pcl_icf_localization's sources: the localizer's pose hypotheses from every
 * source (the whole scene's point pair votes, the clusters' searches) and their one ranking
 * (LocalizerTuning::hypotheses, doc/localizer.md "Hypotheses"). */

#include <pcl/PointIndices.h>
#include <pcl/icf/localization/localizer_tuning.h>
#include <pcl/icf/registration/global_search.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/segmentation/tabletop_segmentation.h>
#include <pcl/icf/verification/depth_image.h>
#include <pcl/icf/verification/depth_verification.h>
#include <pcl_icf_internal/scene_view.h>

#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace pcl {
namespace icf {
namespace localization {
namespace detail {

/** Where a hypothesis came from. */
struct HypothesisSource {
  int cluster = -1;    ///< the cluster (or segment) searched, -1 for the votes
  double votes = 0.0;  ///< the votes' pose cluster's votes (0 for a cluster's search)
};

/** A pose to rank (model -> camera). A voted one is refined on the field by the ranking; a
 * cluster search's already was. */
struct Candidate {
  Eigen::Isometry3f model_to_camera = Eigen::Isometry3f::Identity();
  bool refined = false;
  HypothesisSource source;
};

/** A ranked hypothesis: its field-refined pose, the ranking's confidence, the scene points
 * near it (what the judge refines and explains with). */
struct RankedHypothesis {
  Eigen::Isometry3f model_to_camera = Eigen::Isometry3f::Identity();
  double prescore = 0.0;
  HypothesisSource source;
  pcl::PointIndices near;
};

/** The scene points that may hold the object: above the table when the segmentation found one
 * (the table is a prior where there is one), every usable point when not; never the table's
 * own points nor \a explained ones (another object's accepted pose). */
std::vector<bool> candidatePoints(const internal::SceneView& view,
                                  const segmentation::TabletopSegmentation& segmentation,
                                  const std::vector<int>& explained);

/** The scene subsampled on the model's point pair step with normals (subsampleForVoting),
 * from the points \a usable marks: what the votes come from and what the ranking refines on. */
PointPairScene votingScene(const internal::SceneView& view, const std::vector<bool>& usable,
                           const IcfModel& model, const SceneHypotheses& params, int threads);

/** The poses \a scene votes for (voteForPoses, re-scored against \a image), as candidates to
 * refine. */
std::vector<Candidate> votedCandidates(const IcfModel& model, const PointPairScene& scene,
                                       const DepthImage& image, const SceneHypotheses& params,
                                       int threads);

/** The best per_cluster hypotheses of each cluster's search (globalSearch on its usable points,
 * seeded per cluster), clusters searched in parallel, each into its own slot. */
std::vector<Candidate> clusterCandidates(const internal::SceneView& view,
                                         const std::vector<pcl::PointIndices>& clusters,
                                         const IcfModel& model, const GlobalSearchParams& search,
                                         std::uint64_t seed, const SceneHypotheses& params,
                                         int threads);

/** The one ranking: every candidate refined on the field (the voted ones, with the points of
 * \a scene near them), poses that share the model's surface with an earlier one dropped, the
 * rest verified against \a image in parallel, the most confident distinct ones that reach
 * min_prescore returned best first (at most \a judged), each with the points \a usable marks
 * near it. Deterministic, independent of \a threads. */
std::vector<RankedHypothesis> rankCandidates(
    const internal::SceneView& view, const std::vector<bool>& usable, const IcfModel& model,
    const DepthImage& image, const DepthVerificationParams& verification,
    const PointPairScene& scene, const std::vector<Candidate>& candidates,
    const SceneHypotheses& params, std::size_t judged, int threads);

/** The usable points of \a view that \a usable marks inside \a model's bounding box at \a
 * model_to_camera grown by \a margin on every side. */
pcl::PointIndices pointsInGrownBox(const internal::SceneView& view, const std::vector<bool>& usable,
                                   const IcfModel& model, const Eigen::Isometry3f& model_to_camera,
                                   float margin);

}  // namespace detail
}  // namespace localization
}  // namespace icf
}  // namespace pcl
