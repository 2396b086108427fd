/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/registration/parameter_fields.h>

#include <limits>

namespace pcl {
namespace icf {

namespace {

constexpr double kMaxCount = 1e7;
constexpr double kMaxSeed = 9007199254740992.0;  // 2^53: every seed a double holds exactly

#define PCL_ICF_ACCESS(expr)   \
  [](IcfParams & p) -> auto& { \
    return p.expr;             \
  }
#define PCL_ICF_TUNED(expr)    \
  [](IcfParams & p) -> auto& { \
    return p.tuning().expr;    \
  }

FieldRegistry<IcfParams> makeIcfFields() {
  using P = IcfParams;
  const double inf = std::numeric_limits<double>::infinity();
  return {
      choiceField<P>("strategy", {"fast", "thesis"},
                     "the pose search: the coarse-to-fine field search or the thesis's",
                     PCL_ICF_ACCESS(strategy), &parseSearchStrategy),
      choiceField<P>("fallback", {"off", "auto", "always"},
                     "the SampleConsensus (FPFH) alignment: auto tries it when the search fails",
                     PCL_ICF_ACCESS(fallback), &parseFallbackPolicy),
      numberField<P>("seed", 0, kMaxSeed, "seed of every random choice", PCL_ICF_ACCESS(seed),
                     false),
      numberField<P>("threads", 0, 1024,
                     "threads, 0 for all cores (the result does not depend "
                     "on it)",
                     PCL_ICF_ACCESS(threads), false),
      numberField<P>("rotations", 1, kMaxCount, "rotations the global search tries",
                     PCL_ICF_TUNED(global.rotations)),
      numberField<P>("subsample", 3, kMaxCount, "scene points the coarse search scores",
                     PCL_ICF_TUNED(global.subsample)),
      numberField<P>("prescreen_points", 0, kMaxCount,
                     "points of the prescreen that ranks the rotations",
                     PCL_ICF_TUNED(global.prescreen_points)),
      numberField<P>("prescreen_share", 0, 1, "share of the rotations the prescreen keeps",
                     PCL_ICF_TUNED(global.prescreen_share)),
      numberField<P>("keep", 1, kMaxCount, "hypotheses the search keeps per cluster",
                     PCL_ICF_TUNED(global.keep)),
      numberField<P>("distinct_surface", 0, 1,
                     "hypotheses that put every surface sample within this x the radius of the "
                     "other's surface are one",
                     PCL_ICF_TUNED(global.distinct_surface)),
      numberField<P>("exact_candidates", 1, kMaxCount, "candidates refined against the exact faces",
                     PCL_ICF_TUNED(exact_candidates)),
      numberField<P>("candidate_points", 3, kMaxCount, "points of each candidate's refinement",
                     PCL_ICF_TUNED(candidate_points)),
      numberField<P>("check_candidates", 0, 1,
                     "candidates first checked as the search left them; refused: none refined",
                     PCL_ICF_TUNED(check_candidates)),
      numberField<P>("coarse_points", 0, kMaxCount, "points of the coarse refinement",
                     PCL_ICF_TUNED(coarse_points)),
      numberField<P>("fine_iterations", 1, 100000, "iterations of the fine refinement",
                     PCL_ICF_TUNED(fine_iterations)),
      numberField<P>("max_points", 0, kMaxCount, "the refinement's points per iteration (0: all)",
                     PCL_ICF_TUNED(refinement.max_points)),
      numberField<P>("inlier_distance", 0, inf, "a point within this of the mesh is an inlier",
                     PCL_ICF_ACCESS(acceptance.inlier_distance)),
      numberField<P>("min_surface_coverage", 0, 1,
                     "share of the visible model surface the inliers must cover",
                     PCL_ICF_ACCESS(acceptance.min_surface_coverage)),
      numberField<P>("max_rmse", 0, inf, "largest RMSE of the inliers",
                     PCL_ICF_ACCESS(acceptance.max_rmse)),
      numberField<P>("min_inliers", 0, kMaxCount, "fewest inliers",
                     PCL_ICF_ACCESS(acceptance.min_inliers)),
      numberField<P>("max_seen_through", 0, 1,
                     "largest share of the model seen through (scene points behind its surface)",
                     PCL_ICF_ACCESS(acceptance.max_seen_through)),
      numberField<P>("far_point_gate", 0, 1, "the thesis's far-point gate",
                     PCL_ICF_ACCESS(acceptance.gate.enabled)),
      numberField<P>("gate_distance", 0, inf, "a point farther than this from the model is far",
                     PCL_ICF_ACCESS(acceptance.gate.distance)),
      numberField<P>("gate_max_far_points", 0, kMaxCount,
                     "the gate refuses more than max(this, gate_max_far_fraction x points)",
                     PCL_ICF_ACCESS(acceptance.gate.max_points)),
      numberField<P>("gate_max_far_fraction", 0, 1, "that share of the measured points",
                     PCL_ICF_ACCESS(acceptance.gate.max_fraction)),
  };
}

#undef PCL_ICF_ACCESS
#undef PCL_ICF_TUNED

}  // namespace

const FieldRegistry<IcfParams>& icfFields() {
  static const FieldRegistry<IcfParams> registry = makeIcfFields();
  return registry;
}

}  // namespace icf
}  // namespace pcl
