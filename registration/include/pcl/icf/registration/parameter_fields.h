/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief The field registry: one entry per settable parameter (name, kind, range, one-line
 * doc, how to read and write it), so that the Python keywords, pcl_icf_tool's --set and
 * pcl_icf_bench's overrides call a parameter by one name and their help comes from here. */

#include <pcl/icf/registration/estimate_pose.h>

#include <functional>
#include <string>
#include <vector>

namespace pcl {
namespace icf {

enum class FieldKind {
  Flag,    ///< 0 or 1 (false, true)
  Count,   ///< a whole number in [min, max]
  Real,    ///< a number in [min, max]
  Choice,  ///< one of choices, by name
};

/** \brief What a settable field is, whatever struct holds it: its name, kind, range and doc. */
struct FieldDescription {
  std::string name;
  FieldKind kind = FieldKind::Real;
  double min = 0.0, max = 0.0;       ///< Count, Real
  std::vector<std::string> choices;  ///< Choice
  bool single = false;               ///< the member is a float: its text is a float's
  bool tuning = false;               ///< a calibration constant, not a user's knob
  std::string doc;                   ///< one line
};

/** \brief One settable field of \a Params. Numbers are read and written as doubles (a count
 * up to 2^53 exactly); a Choice by its name. Cross-field rules (max_residual above
 * fit_residual, ...) stay with Params::validate(), called on the whole struct after setting. */
template <typename Params>
struct ParameterField : FieldDescription {
  std::function<void(Params&, double)> set_number;
  std::function<double(const Params&)> get_number;
  std::function<void(Params&, const std::string&)> set_choice;
  std::function<std::string(const Params&)> get_choice;
};

template <typename Params>
using FieldRegistry = std::vector<ParameterField<Params>>;

/** The field called \a name. \throws std::invalid_argument naming the known fields. */
template <typename Params>
const ParameterField<Params>& findField(const FieldRegistry<Params>& registry,
                                        const std::string& name);

/** Sets \a field of \a params to \a value. \throws std::invalid_argument("NAME: ...") for a
 * value of the wrong kind (a fraction for a count, 2 for a flag) or outside [min, max]. */
template <typename Params>
void setFieldNumber(const ParameterField<Params>& field, Params& params, double value);

/** Sets \a field from text: a number, a flag's 0/1/true/false or a choice's name.
 * \throws std::invalid_argument("NAME: ..."). */
template <typename Params>
void setFieldText(const ParameterField<Params>& field, Params& params, const std::string& text);

/** \a field's value in \a params as text (a number as the shortest text that reads back the
 * same, a flag as 0 or 1, a choice by name). */
template <typename Params>
std::string fieldText(const ParameterField<Params>& field, const Params& params);

/** "name  kind [min, max] (default: D)  doc" lines, one per field, defaults from Params{}. */
template <typename Params>
std::string describeFields(const FieldRegistry<Params>& registry);

/** A number field reached through \a access (a function Params& -> T&, T an arithmetic type
 * or bool): kind Flag for bool, Count for an integer, Real otherwise. */
template <typename Params, typename Access>
ParameterField<Params> numberField(std::string name, double min, double max, std::string doc,
                                   Access access, bool tuning = true);

/** A Choice field reached through \a access (Params& -> T&), read by \a parse (name -> T,
 * throwing std::invalid_argument) and written by toString(T). */
template <typename Params, typename T, typename Access>
ParameterField<Params> choiceField(std::string name, std::vector<std::string> choices,
                                   std::string doc, Access access, T (*parse)(const std::string&),
                                   bool tuning = false);

/** \a registry's fields as fields of \a Outer, reaching the inner struct through \a access
 * (Outer& -> Inner&), their names and docs unchanged. */
template <typename Outer, typename Inner, typename Access>
FieldRegistry<Outer> liftFields(const FieldRegistry<Inner>& registry, Access access);

/** The registered fields of IcfParams (estimatePose, IterativeClosestFace): the search, its
 * acceptance and the far-point gate, by their Python keyword names. */
const FieldRegistry<IcfParams>& icfFields();

}  // namespace icf
}  // namespace pcl

#include <pcl/icf/registration/impl/parameter_fields.hpp>
