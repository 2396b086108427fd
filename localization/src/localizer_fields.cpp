/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/localization/localizer_fields.h>

#include <algorithm>
#include <limits>

namespace pcl {
namespace icf {
namespace localization {

namespace {

constexpr double kMaxCount = 1e7;

#define PCL_ICF_OWN(expr)            \
  [](LocalizerParams & p) -> auto& { \
    return p.expr;                   \
  }
#define PCL_ICF_TUNING(expr)         \
  [](LocalizerParams & p) -> auto& { \
    return p.tuning().expr;          \
  }

/** The fields LocalizerParams has itself. */
FieldRegistry<LocalizerParams> ownFields() {
  using P = LocalizerParams;
  const double inf = std::numeric_limits<double>::infinity();
  FieldRegistry<P> f = {
      numberField<P>("segment", 0, 1, "0: the cloud is one object's cluster already",
                     PCL_ICF_OWN(segment), false),
      numberField<P>("cluster_tolerance", 0, inf, "the Euclidean clusters' distance",
                     PCL_ICF_OWN(cluster.tolerance), false),
      numberField<P>("min_cluster_size", 1, 1e8, "fewest points of a cluster",
                     PCL_ICF_OWN(cluster.min_size), false),
      numberField<P>("max_cluster_size", 1, 1e9, "most points of a cluster",
                     PCL_ICF_OWN(cluster.max_size), false),
      numberField<P>("split_merged", 0, 1,
                     "a cluster wider than the model is also split where it turns concave",
                     PCL_ICF_OWN(split_merged), false),
      numberField<P>("max_instances", 1, 1000, "copies reported, best first",
                     PCL_ICF_OWN(max_instances), false),
      numberField<P>("check_turns", 0, 1, "look-alike turns about the principal axes are tried",
                     PCL_ICF_OWN(check_turns), false),
      numberField<P>("colour_weight", 0, inf, "weight of the colour cue in the ranking",
                     PCL_ICF_OWN(colour.weight), false),
      numberField<P>("min_confidence", 0, 1, "a pose is accepted at this confidence",
                     PCL_ICF_OWN(min_confidence), false),
      numberField<P>("mesh_accuracy", 0, 0.05,
                     "how far the mesh's surface may lie from the object's, metres (CAD 0, "
                     "scanned 0.001-0.002)",
                     PCL_ICF_OWN(mesh_accuracy), false),
      numberField<P>("depth_noise", 0, 1,
                     "the camera's depth noise (sigma) at 1 m, metres; grows with z^2",
                     PCL_ICF_OWN(depth_noise.coefficient), false),
      numberField<P>("depth_noise_floor", 1e-6, 1, "the camera's smallest depth sigma, metres",
                     PCL_ICF_OWN(depth_noise.floor), false),
      numberField<P>("depth_systematic", 0, 1,
                     "the camera's low-frequency depth error at 1 m, metres; grows with z^2 "
                     "(a simulated camera: 0)",
                     PCL_ICF_OWN(depth_noise.systematic), false),
  };
  // The registration's strategy, fallback, seed and threads are the localizer's own.
  f.push_back(choiceField<P>("strategy", {"fast", "thesis"}, findField(icfFields(), "strategy").doc,
                             PCL_ICF_OWN(strategy), &parseSearchStrategy));
  f.push_back(choiceField<P>("fallback", {"off", "auto", "always"},
                             findField(icfFields(), "fallback").doc, PCL_ICF_OWN(fallback),
                             &parseFallbackPolicy));
  f.push_back(numberField<P>("seed", 0, findField(icfFields(), "seed").max,
                             "seed of every random choice", PCL_ICF_OWN(seed), false));
  f.push_back(numberField<P>("threads", 0, 1024,
                             "threads of the clusters and of each search, 0 for all cores",
                             PCL_ICF_OWN(threads), false));
  return f;
}

/** The calibration constants under tuning() that are not the registration's. */
FieldRegistry<LocalizerParams> tuningFields() {
  using P = LocalizerParams;
  const double inf = std::numeric_limits<double>::infinity();
  return {
      numberField<P>("refine_min_confidence", 0, 1,
                     "a search start below this confidence is not refined",
                     PCL_ICF_TUNING(refine_min_confidence)),
      numberField<P>("promising_share", 0, 1,
                     "share of min_confidence from which a judged pose's turns and last "
                     "refinement are tried",
                     PCL_ICF_TUNING(promising_share)),
      numberField<P>("max_shared_points", 0, 1,
                     "two instances sharing more of their points are one",
                     PCL_ICF_TUNING(max_shared_points)),
      numberField<P>("min_points_in_front", 0, 1,
                     "share of the scene that must lie in front of the camera",
                     PCL_ICF_TUNING(min_points_in_front)),
      numberField<P>("turn_points", 0, kMaxCount, "points of each turn's refinement",
                     PCL_ICF_TUNING(alternatives.max_points)),
      numberField<P>("fit_residual", 0, inf,
                     "the verification's full-confidence depth residual, in noise sigmas",
                     PCL_ICF_TUNING(verification.fit_residual)),
      numberField<P>("max_residual", 0, inf, "its zero-confidence residual (inf: off)",
                     PCL_ICF_TUNING(verification.max_residual)),
      numberField<P>("full_evidence", 0, 1,
                     "share of the visible model the depth must support for full confidence",
                     PCL_ICF_TUNING(verification.full_evidence)),
      numberField<P>("out_of_view_evidence", 0, inf,
                     "more support needed per share of the model beyond the image's border",
                     PCL_ICF_TUNING(verification.out_of_view_evidence)),
      numberField<P>("edge_offset_pixels", 0, inf,
                     "the scene's edges may lie this far from the model's silhouette, pixels",
                     PCL_ICF_TUNING(verification.edge_offset_pixels)),
      numberField<P>("min_edge_pixels", 0, kMaxCount,
                     "silhouette pixels whose edge was found the offset needs",
                     PCL_ICF_TUNING(verification.min_edge_pixels)),
      numberField<P>("sink_tolerances", 0, inf,
                     "how deep a model may sink into its support, in support tolerances",
                     PCL_ICF_TUNING(verification.sink_tolerances)),
      numberField<P>("max_conflict", 0, 1, "largest share of the model seen through",
                     PCL_ICF_TUNING(verification.max_conflict)),
      numberField<P>("max_continuation", 0, 1,
                     "largest share of the silhouette where the surface carries on",
                     PCL_ICF_TUNING(verification.max_continuation)),
      numberField<P>("support_occlusion", 0, inf,
                     "share of the model its own support may hide, half the zero-confidence one",
                     PCL_ICF_TUNING(verification.support_occlusion)),
      numberField<P>("crease_window", 0, 1,
                     "window of the planes telling a crease, share of the model's diameter",
                     PCL_ICF_TUNING(verification.crease_window)),
      numberField<P>("local_misfit", 0, inf,
                     "largest tile's mean offset from the depth, in its uncertainties, with "
                     "full confidence (0 at twice it; inf: off)",
                     PCL_ICF_TUNING(verification.local_misfit)),
      numberField<P>("misfit_tile", 0, 1,
                     "side of the misfit's tiles, share of the diameter (4-40 pixels)",
                     PCL_ICF_TUNING(verification.misfit_tile)),
      numberField<P>("point_pairs", 0, 1, "hypotheses from the whole scene's point pair votes",
                     PCL_ICF_TUNING(hypotheses.point_pairs)),
      numberField<P>("clusters", 0, 1, "hypotheses from each cluster's search",
                     PCL_ICF_TUNING(hypotheses.clusters)),
      numberField<P>("pp_spread", 0, 0.5,
                     "a feature this near a bin's border also looks up the neighbour",
                     PCL_ICF_TUNING(hypotheses.voting.spread_margin)),
      numberField<P>("pp_kept", 1, kMaxCount, "voted hypotheses the ranking verifies",
                     PCL_ICF_TUNING(hypotheses.voting.kept)),
      numberField<P>("pp_kept_visible", 0, kMaxCount,
                     "more voted hypotheses, by the share of what they show that is explained",
                     PCL_ICF_TUNING(hypotheses.voting.kept_visible)),
      numberField<P>("pp_per_place", 1, kMaxCount, "of the kept, most at one place",
                     PCL_ICF_TUNING(hypotheses.voting.kept_per_place)),
      numberField<P>("pp_references", 1, kMaxCount, "reference points over the whole frame",
                     PCL_ICF_TUNING(hypotheses.voting.max_references)),
      numberField<P>("pp_max_pairs", 1, inf,
                     "a reference pairs with at most this many discs of the model's points",
                     PCL_ICF_TUNING(hypotheses.voting.max_pairs_discs)),
      numberField<P>("pp_max_scene_points", 0, kMaxCount,
                     "the votes come from at most this many scene points (0: no limit)",
                     PCL_ICF_TUNING(hypotheses.max_voting_points)),
      numberField<P>("pp_rescored", 1, kMaxCount, "vote clusters re-scored on the scene",
                     PCL_ICF_TUNING(hypotheses.voting.rescored)),
      numberField<P>("pp_reference_share", 0, 1, "share of the points used as references",
                     PCL_ICF_TUNING(hypotheses.voting.reference_share)),
      numberField<P>("pp_peaks", 1, 16, "poses taken from each reference's accumulator",
                     PCL_ICF_TUNING(hypotheses.voting.peaks_per_reference)),
      numberField<P>("per_cluster", 0, kMaxCount, "a cluster search's hypotheses ranked",
                     PCL_ICF_TUNING(hypotheses.per_cluster)),
      numberField<P>("judged", 1, kMaxCount, "the most confident hypotheses judged",
                     PCL_ICF_TUNING(hypotheses.judged)),
      numberField<P>("per_location", 1, kMaxCount, "of the judged, most at one place",
                     PCL_ICF_TUNING(hypotheses.per_location)),
      numberField<P>("min_prescore", 0, 1, "ranking confidence a judged hypothesis needs",
                     PCL_ICF_TUNING(hypotheses.min_prescore)),
      numberField<P>("hypothesis_crop_margin", 0, inf,
                     "a hypothesis is judged on the points in its box grown by this x diameter",
                     PCL_ICF_TUNING(hypotheses.crop_margin)),
      numberField<P>("refine_points", 10, kMaxCount, "points of a hypothesis's refinement",
                     PCL_ICF_TUNING(hypotheses.refine_points)),
      numberField<P>("final_points", 10, kMaxCount,
                     "points of the last refinement of a promising pose",
                     PCL_ICF_TUNING(hypotheses.final_points)),
  };
}

#undef PCL_ICF_OWN
#undef PCL_ICF_TUNING

FieldRegistry<LocalizerParams> makeLocalizerFields() {
  using P = LocalizerParams;
  FieldRegistry<P> all = ownFields();
  const auto own = [&all](const std::string& name) {
    return std::any_of(all.begin(), all.end(), [&](const auto& f) { return f.name == name; });
  };
  for (auto& f :
       liftFields<P, IcfParams>(icfFields(), [](P& p) -> IcfParams& { return p.tuning().icf; }))
    if (!own(f.name))
      all.push_back(std::move(f));
  for (auto& f : tuningFields())
    all.push_back(std::move(f));
  return all;
}

}  // namespace

const FieldRegistry<LocalizerParams>& localizerFields() {
  static const FieldRegistry<LocalizerParams> registry = makeLocalizerFields();
  return registry;
}

}  // namespace localization
}  // namespace icf
}  // namespace pcl
