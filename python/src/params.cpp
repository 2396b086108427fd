/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "params.h"

#include <pcl/icf/localization/localizer_fields.h>
#include <pcl/icf/registration/parameter_fields.h>
#include <pcl/icf/tracking/tracker_fields.h>

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

/** A registered field (parameter_fields.h) as a keyword: a flag takes a bool, a count an
 * int, a real a number, a choice its name; the registry checks the value. */
template <typename Params>
Field<Params> registered(const pcl::icf::ParameterField<Params>& f) {
  using pcl::icf::FieldKind;
  return {[f](Params& p, const py::handle& v) {
            if (f.kind == FieldKind::Choice)
              pcl::icf::setFieldText(f, p, v.cast<std::string>());
            else if (f.kind == FieldKind::Flag)
              pcl::icf::setFieldNumber(f, p, v.cast<bool>() ? 1.0 : 0.0);
            else if (f.kind == FieldKind::Count)
              pcl::icf::setFieldNumber(f, p, static_cast<double>(v.cast<long long>()));
            else
              pcl::icf::setFieldNumber(f, p, v.cast<double>());
          },
          [f](const Params& p) -> py::object {
            switch (f.kind) {
              case FieldKind::Choice:
                return py::str(f.get_choice(p));
              case FieldKind::Flag:
                return py::bool_(f.get_number(p) != 0.0);
              case FieldKind::Count:
                return py::int_(static_cast<long long>(f.get_number(p)));
              case FieldKind::Real:
                break;
            }
            return py::float_(f.get_number(p));
          }};
}

template <typename Params>
FieldTable<Params> registeredTable(const pcl::icf::FieldRegistry<Params>& registry) {
  FieldTable<Params> t;
  for (const auto& f : registry)
    t[f.name] = registered(f);
  return t;
}

FieldTable<pcl::icf::IcfParams> icfTable() {
  return registeredTable(pcl::icf::icfFields());
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
  FieldTable<P> t = registeredTable(localization::localizerFields());
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
  FieldTable<P> t = registeredTable(pcl::icf::tracking::trackerFields());
  // Every localize() keyword sets the search and the verification (TrackerParams::localizer).
  for (auto& [name, field] : localizerTable())
    t[name] = {[set = field.set](P& p, const py::handle& v) { set(p.localizer, v); },
               [get = field.get](const P& p) { return get(p.localizer); }};
  return t;
}

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
      // The registry's messages name the field already.
      const std::string what = e.what();
      throw py::value_error(what.rfind(name + ":", 0) == 0 ? what : name + ": " + what);
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

const FieldTable<localization::LocalizerParams>& localizerKeywords() {
  static const auto table = localizerTable();
  return table;
}

const FieldTable<pcl::icf::IcfParams>& icfKeywords() {
  static const auto table = icfTable();
  return table;
}

const FieldTable<pcl::icf::tracking::TrackerParams>& trackerKeywords() {
  static const auto table = trackerTable();
  return table;
}

/** \a kwargs, refused with the replacement when they hold exact_mesh (gone: one rule verifies
 * every mesh). */
const py::kwargs& withoutExactMesh(const py::kwargs& kwargs) {
  for (const auto& item : kwargs)
    if (item.first.cast<std::string>() == "exact_mesh")
      throw py::type_error(
          "exact_mesh is gone: one rule verifies every mesh. A mesh that differs from the "
          "object: mesh_accuracy=M (metres); a simulated camera without low-frequency depth "
          "error: depth_systematic=0");
  return kwargs;
}

}  // namespace

void applyLocalizerKwargs(localization::LocalizerParams& params, const py::kwargs& kwargs) {
  apply(localizerKeywords(), params, withoutExactMesh(kwargs), "localize");
}

void applyIcfKwargs(pcl::icf::IcfParams& params, const py::kwargs& kwargs) {
  apply(icfKeywords(), params, kwargs, "estimate_pose");
}

void applyTrackerKwargs(pcl::icf::tracking::TrackerParams& params, const py::kwargs& kwargs) {
  apply(trackerKeywords(), params, withoutExactMesh(kwargs), "Tracker");
}

py::dict trackerDefaults() {
  return defaults(trackerKeywords());
}

py::dict localizerDefaults() {
  return defaults(localizerKeywords());
}

py::dict icfDefaults() {
  return defaults(icfKeywords());
}

py::list localizerFieldList() {
  static const char* const kinds[] = {"flag", "count", "real", "choice"};
  const localization::LocalizerParams defaults;
  py::list out;
  for (const auto& f : localization::localizerFields()) {
    py::dict d;
    d["name"] = f.name;
    d["kind"] = kinds[static_cast<int>(f.kind)];
    d["min"] = f.min;
    d["max"] = f.max;
    d["choices"] = f.choices;
    d["default"] = localizerKeywords().at(f.name).get(defaults);
    d["tuning"] = f.tuning;
    d["doc"] = f.doc;
    out.append(d);
  }
  return out;
}

const std::string& keywordDoc(bool tracker) {
  static const std::string localizer =
      "\n\nKeywords (name kind [range] = default  meaning; fields() lists them):\n" +
      pcl::icf::describeFields(localization::localizerFields()) +
      "colour  (r, g, b) in [0, 1] or None = None  the object's colour\n"
      "intrinsics  dict fx, fy, cx, cy, width, height or None = None  an unorganized "
      "cloud's camera\n";
  static const std::string with_tracker =
      "\n\nThe tracker's own keywords:\n" +
      pcl::icf::describeFields(pcl::icf::tracking::trackerFields()) + localizer;
  return tracker ? with_tracker : localizer;
}

}  // namespace pcl_icf_python
