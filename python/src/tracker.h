/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pybind11/pybind11.h>

namespace pcl_icf_python {

/** \brief Adds pcl_icf.Tracker (pcl::icf::tracking::ObjectTracker) and tracker_defaults() to
 * \a m. */
void bindTracker(pybind11::module_& m);

}  // namespace pcl_icf_python
