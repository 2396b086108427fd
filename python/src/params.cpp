/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "params.h"

#include <pybind11/stl.h>

#include <functional>
#include <map>
#include <stdexcept>
#include <string>

namespace pcl_icf_python {

namespace localization = pcl::icf::localization;

namespace {

template <typename Params>
struct Field {
  std::function<void(Params&, const py::handle&)> set;
  std::function<py::object(const Params&)> get;
};

template <typename Params>
using FieldTable = std::map<std::string, Field<Params>>;

/** A plain member reached through \a access (a lambda returning a reference). */
template <typename Params, typename T, typename Access>
Field<Params> member(Access access) {
  return {[access](Params& p, const py::handle& v) { access(p) = v.cast<T>(); },
          [access](const Params& p) { return py::cast(access(const_cast<Params&>(p))); }};
}

#define PCL_ICF_FIELD(Params, T, expr) member<Params, T>([](Params& p) -> T& { return p.expr; })

/** An enum member given by its name: \a parse reads it, pcl::icf::toString writes it. */
template <typename Params, typename T, typename Access>
Field<Params> named(Access access, T (*parse)(const std::string&)) {
  return {
      [access, parse](Params& p, const py::handle& v) { access(p) = parse(v.cast<std::string>()); },
      [access](const Params& p) {
        return py::cast(pcl::icf::toString(access(const_cast<Params&>(p))));
      }};
}

#define PCL_ICF_NAMED(Params, T, expr, parse) \
  named<Params, T>([](Params& p) -> T& { return p.expr; }, &pcl::icf::parse)

FieldTable<pcl::icf::IcfParams> icfTable() {
  using P = pcl::icf::IcfParams;
  FieldTable<P> t;
  t["seed"] = PCL_ICF_FIELD(P, std::uint64_t, seed);
  t["threads"] = PCL_ICF_FIELD(P, int, threads);
  t["exact_candidates"] = PCL_ICF_FIELD(P, std::size_t, exact_candidates);
  t["candidate_points"] = PCL_ICF_FIELD(P, std::size_t, candidate_points);
  t["check_candidates"] = PCL_ICF_FIELD(P, bool, check_candidates);
  t["coarse_points"] = PCL_ICF_FIELD(P, std::size_t, coarse_points);
  t["fine_iterations"] = PCL_ICF_FIELD(P, int, fine_iterations);
  t["prescreen_share"] = PCL_ICF_FIELD(P, float, global.prescreen_share);
  t["inlier_distance"] = PCL_ICF_FIELD(P, float, acceptance.inlier_distance);
  t["min_surface_coverage"] = PCL_ICF_FIELD(P, double, acceptance.min_surface_coverage);
  t["max_rmse"] = PCL_ICF_FIELD(P, double, acceptance.max_rmse);
  t["min_inliers"] = PCL_ICF_FIELD(P, std::size_t, acceptance.min_inliers);
  t["max_seen_through"] = PCL_ICF_FIELD(P, double, acceptance.max_seen_through);
  t["far_point_gate"] = PCL_ICF_FIELD(P, bool, acceptance.gate.enabled);
  t["gate_distance"] = PCL_ICF_FIELD(P, float, acceptance.gate.distance);
  t["gate_max_far_points"] = PCL_ICF_FIELD(P, int, acceptance.gate.max_points);
  t["gate_max_far_fraction"] = PCL_ICF_FIELD(P, double, acceptance.gate.max_fraction);
  t["rotations"] = PCL_ICF_FIELD(P, std::size_t, global.rotations);
  t["keep"] = PCL_ICF_FIELD(P, std::size_t, global.keep);
  t["distinct_surface"] = PCL_ICF_FIELD(P, float, global.distinct_surface);
  t["max_points"] = PCL_ICF_FIELD(P, std::size_t, refinement.max_points);
  t["strategy"] = PCL_ICF_NAMED(P, pcl::icf::SearchStrategy, strategy, parseSearchStrategy);
  t["fallback"] = PCL_ICF_NAMED(P, pcl::icf::FallbackPolicy, fallback, parseFallbackPolicy);
  return t;
}

pcl::icf::PinholeIntrinsics intrinsicsOf(const py::handle& v) {
  pcl::icf::PinholeIntrinsics k;
  if (!py::isinstance<py::dict>(v))
    throw py::value_error("intrinsics: expected a dict with fx, fy, cx, cy, width, height");
  for (const auto& item : v.cast<py::dict>()) {
    const auto key = item.first.cast<std::string>();
    if (key == "fx")
      k.fx = item.second.cast<float>();
    else if (key == "fy")
      k.fy = item.second.cast<float>();
    else if (key == "cx")
      k.cx = item.second.cast<float>();
    else if (key == "cy")
      k.cy = item.second.cast<float>();
    else if (key == "width")
      k.width = item.second.cast<int>();
    else if (key == "height")
      k.height = item.second.cast<int>();
    else
      throw py::value_error("intrinsics: unknown key '" + key +
                            "' (expected fx, fy, cx, cy, width, height)");
  }
  return k;
}

FieldTable<localization::LocalizerParams> localizerTable() {
  using P = localization::LocalizerParams;
  FieldTable<P> t;
  for (auto& [name, field] : icfTable())
    t[name] = {[set = field.set](P& p, const py::handle& v) { set(p.tuning().icf, v); },
               [get = field.get](const P& p) { return get(p.tuning().icf); }};
  // The registration's fields the localizer has itself (LocalizerParams::icfParams).
  t["threads"] = PCL_ICF_FIELD(P, int, threads);
  t["seed"] = PCL_ICF_FIELD(P, std::uint64_t, seed);
  t["strategy"] = PCL_ICF_NAMED(P, pcl::icf::SearchStrategy, strategy, parseSearchStrategy);
  t["fallback"] = PCL_ICF_NAMED(P, pcl::icf::FallbackPolicy, fallback, parseFallbackPolicy);
  t["segment"] = PCL_ICF_FIELD(P, bool, segment);
  t["min_confidence"] = PCL_ICF_FIELD(P, double, min_confidence);
  t["refine_min_confidence"] = PCL_ICF_FIELD(P, double, tuning().refine_min_confidence);
  t["max_instances"] = PCL_ICF_FIELD(P, int, max_instances);
  t["max_shared_points"] = PCL_ICF_FIELD(P, double, tuning().max_shared_points);
  t["min_points_in_front"] = PCL_ICF_FIELD(P, double, tuning().min_points_in_front);
  t["split_merged"] = PCL_ICF_FIELD(P, bool, split_merged);
  t["check_turns"] = PCL_ICF_FIELD(P, bool, check_turns);
  t["turn_points"] = PCL_ICF_FIELD(P, std::size_t, tuning().alternatives.max_points);
  t["fit_residual"] = PCL_ICF_FIELD(P, double, tuning().verification.fit_residual);
  t["max_residual"] = PCL_ICF_FIELD(P, double, tuning().verification.max_residual);
  t["full_evidence"] = PCL_ICF_FIELD(P, double, tuning().verification.full_evidence);
  t["max_conflict"] = PCL_ICF_FIELD(P, double, tuning().verification.max_conflict);
  t["max_continuation"] = PCL_ICF_FIELD(P, double, tuning().verification.max_continuation);
  t["cluster_tolerance"] = PCL_ICF_FIELD(P, double, cluster.tolerance);
  t["min_cluster_size"] = PCL_ICF_FIELD(P, std::size_t, cluster.min_size);
  t["max_cluster_size"] = PCL_ICF_FIELD(P, std::size_t, cluster.max_size);
  t["colour_weight"] = PCL_ICF_FIELD(P, double, colour.weight);
  t["colour"] = {[](P& p, const py::handle& v) {
                   if (v.is_none()) {
                     p.colour.expected.reset();
                     return;
                   }
                   const auto c = v.cast<std::vector<float>>();
                   if (c.size() != 3)
                     throw py::value_error("colour: expected (r, g, b) in [0, 1] or None");
                   p.colour.expected = Eigen::Vector3f(c[0], c[1], c[2]);
                 },
                 [](const P& p) {
                   return p.colour.expected
                              ? py::cast(std::vector<float>(p.colour.expected->data(),
                                                            p.colour.expected->data() + 3))
                              : py::none().cast<py::object>();
                 }};
  t["intrinsics"] = {[](P& p, const py::handle& v) {
                       if (v.is_none())
                         p.intrinsics.reset();
                       else
                         p.intrinsics = intrinsicsOf(v);
                     },
                     [](const P& p) {
                       if (!p.intrinsics)
                         return py::none().cast<py::object>();
                       const auto& k = *p.intrinsics;
                       return py::dict(py::arg("fx") = k.fx, py::arg("fy") = k.fy,
                                       py::arg("cx") = k.cx, py::arg("cy") = k.cy,
                                       py::arg("width") = k.width, py::arg("height") = k.height)
                           .cast<py::object>();
                     }};
  return t;
}

FieldTable<pcl::icf::tracking::TrackerParams> trackerTable() {
  using P = pcl::icf::tracking::TrackerParams;
  FieldTable<P> t;
  // Every localize() keyword sets the search and the verification (TrackerParams::localizer).
  for (auto& [name, field] : localizerTable())
    t[name] = {[set = field.set](P& p, const py::handle& v) { set(p.localizer, v); },
               [get = field.get](const P& p) { return get(p.localizer); }};
  t["crop_margin"] = PCL_ICF_FIELD(P, float, crop_margin);
  t["table_distance"] = PCL_ICF_FIELD(P, float, table_distance);
  t["velocity_gain"] = PCL_ICF_FIELD(P, float, velocity_gain);
  t["search_interval"] = PCL_ICF_FIELD(P, int, search_interval);
  t["reacquire_margin"] = PCL_ICF_FIELD(P, float, reacquire_margin);
  t["reacquire_frames"] = PCL_ICF_FIELD(P, int, reacquire_frames);
  t["reacquire_shift"] = PCL_ICF_FIELD(P, float, reacquire_shift);
  t["reacquire_full_evidence"] = PCL_ICF_FIELD(P, double, reacquire_full_evidence);
  t["refine_max_points"] = PCL_ICF_FIELD(P, std::size_t, refinement.max_points);
  return t;
}

#undef PCL_ICF_FIELD
#undef PCL_ICF_NAMED

template <typename Params>
void apply(const FieldTable<Params>& table, Params& params, const py::kwargs& kwargs,
           const char* function) {
  for (const auto& item : kwargs) {
    const auto name = item.first.cast<std::string>();
    const auto field = table.find(name);
    if (field == table.end())
      throw py::type_error(std::string(function) + "() got an unexpected keyword argument '" +
                           name + "'");
    try {
      field->second.set(params, item.second);
    } catch (const py::cast_error&) {
      throw py::type_error(name + ": cannot take " + py::repr(item.second).cast<std::string>());
    } catch (const std::invalid_argument& e) {
      throw py::value_error(name + ": " + e.what());
    }
  }
  params.validate();
}

template <typename Params>
py::dict defaults(const FieldTable<Params>& table) {
  const Params params;
  py::dict d;
  for (const auto& [name, field] : table)
    d[py::str(name)] = field.get(params);
  return d;
}

const FieldTable<localization::LocalizerParams>& localizerFields() {
  static const auto table = localizerTable();
  return table;
}

const FieldTable<pcl::icf::IcfParams>& icfFields() {
  static const auto table = icfTable();
  return table;
}

const FieldTable<pcl::icf::tracking::TrackerParams>& trackerFields() {
  static const auto table = trackerTable();
  return table;
}

/** \a kwargs less exact_mesh, which is applied to \a params first (useExactMeshSettings when
 * true), as the tool's --exact-mesh: the keywords given with it win. */
py::kwargs withExactMesh(localization::LocalizerParams& params, const py::kwargs& kwargs) {
  py::kwargs rest;
  for (const auto& item : kwargs) {
    if (item.first.cast<std::string>() != "exact_mesh") {
      rest[item.first] = item.second;
      continue;
    }
    // Strictly a bool: a switch that 0.8 or None silently turned off would hide a mistake.
    if (!py::isinstance<py::bool_>(item.second))
      throw py::type_error("exact_mesh: cannot take " + py::repr(item.second).cast<std::string>() +
                           " (True or False)");
    if (item.second.cast<bool>())
      params.useExactMeshSettings();
  }
  return rest;
}

}  // namespace

void applyLocalizerKwargs(localization::LocalizerParams& params, const py::kwargs& kwargs) {
  apply(localizerFields(), params, withExactMesh(params, kwargs), "localize");
}

void applyIcfKwargs(pcl::icf::IcfParams& params, const py::kwargs& kwargs) {
  apply(icfFields(), params, kwargs, "estimate_pose");
}

void applyTrackerKwargs(pcl::icf::tracking::TrackerParams& params, const py::kwargs& kwargs) {
  apply(trackerFields(), params, withExactMesh(params.localizer, kwargs), "Tracker");
}

py::dict trackerDefaults() {
  return defaults(trackerFields());
}

py::dict localizerDefaults() {
  return defaults(localizerFields());
}

py::dict icfDefaults() {
  return defaults(icfFields());
}

}  // namespace pcl_icf_python
