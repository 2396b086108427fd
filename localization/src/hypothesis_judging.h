/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Private to pcl_icf_localization's sources: judging the ranked hypotheses, each on the
 * points near it: its pose refined by ICF, the depth verification that decides, the thesis's
 * gate, the colour cue, its turns, and the reason of a refusal (doc/localizer.md). */

#include <pcl/icf/localization/object_localizer.h>
#include <pcl_icf_internal/scene_view.h>

#include "scene_hypotheses.h"

#include <vector>

namespace pcl::icf::localization::detail {

/** Every ranked hypothesis judged (from its pose, on the points near it), in parallel, each
 * into its own slot; the same result at any thread count. */
std::vector<ClusterLocalization> judgeHypotheses(const internal::SceneView& view,
                                                 const DepthImage& image, const IcfModel& model,
                                                 const LocalizerParams& params,
                                                 const std::vector<RankedHypothesis>& ranked,
                                                 int threads);

}  // namespace pcl::icf::localization::detail
