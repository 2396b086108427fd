/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pybind11/pybind11.h>

#include <pcl/icf/localization/object_localizer.h>
#include <pcl/icf/registration/estimate_pose.h>
#include <pcl/icf/tracking/object_tracker.h>

namespace pcl_icf_python {

namespace py = pybind11;

/** \brief Applies keyword arguments to \a params (names in python/README: the LocalizerParams
 * fields, the tool's shortcuts for nested ones), then params.validate().
 * \throws py::type_error for an unknown name, std::invalid_argument (ValueError) from
 * validate(). */
void applyLocalizerKwargs(pcl::icf::localization::LocalizerParams& params,
                          const py::kwargs& kwargs);

/** \brief The same for estimatePose's IcfParams (the icf subset of the names). */
void applyIcfKwargs(pcl::icf::IcfParams& params, const py::kwargs& kwargs);

/** \brief The same for the Tracker's TrackerParams: every localize() keyword (the search and
 * the verification) and the tracker's own (crop_margin, table_distance, velocity_gain,
 * search_interval, reacquire_margin, reacquire_frames,
 * reacquire_shift, reacquire_full_evidence, refine_max_points). */
void applyTrackerKwargs(pcl::icf::tracking::TrackerParams& params, const py::kwargs& kwargs);

/** \brief Every keyword Tracker() takes, with its C++ default. */
py::dict trackerDefaults();

/** \brief Every keyword localize() takes, with its C++ default. */
py::dict localizerDefaults();

/** \brief Every keyword estimate_pose() takes, with its C++ default. */
py::dict icfDefaults();

/** \brief The registered fields of localize() (localizerFields()), one dict each: name, kind,
 * min, max, choices, default, tuning, doc. */
py::list localizerFieldList();

/** \brief "Keywords:" and one line per registered field (describeFields), for a docstring:
 * of localize() (\a tracker false) or of Tracker() (true: the tracker's own first). */
const std::string& keywordDoc(bool tracker);

}  // namespace pcl_icf_python
