/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "results.h"

#include <utility>

namespace pcl_icf_python {

py::object makeNamespace(py::dict fields) {
  static const py::object simple = py::module_::import("types").attr("SimpleNamespace");
  return simple(**fields);
}

py::dict verificationDict(const pcl::icf::DepthExplanation& v) {
  using E = pcl::icf::DepthExplanation;
  static const std::pair<const char*, double E::*> kTerms[] = {
      {"confidence", &E::confidence},
      {"supported", &E::supported},
      {"seen_through", &E::seen_through},
      {"occluded", &E::occluded},
      {"below_support", &E::below_support},
      {"isolated_conflicts", &E::isolated_conflicts},
      {"missing", &E::missing},
      {"out_of_view", &E::out_of_view},
      {"on_background", &E::on_background},
      {"visible_support", &E::visible_support},
      {"residual", &E::residual},
      {"silhouette_continuation", &E::silhouette_continuation},
      {"occluder_continuation", &E::occluder_continuation},
      {"occluded_by_support", &E::occluded_by_support},
      {"local_misfit", &E::local_misfit},
      {"silhouette_offset", &E::silhouette_offset},
      {"allowed_offset", &E::allowed_offset},
      {"sunk_into_support", &E::sunk_into_support},
      {"support_tolerance", &E::support_tolerance}};
  py::dict d;
  for (const auto& [name, term] : kTerms)
    d[name] = v.*term;
  d["judged_pixels"] = v.model_pixels;
  d["silhouette_pixels"] = v.silhouette_pixels;
  d["silhouette_edges"] = v.silhouette_edges;
  return d;
}

}  // namespace pcl_icf_python
