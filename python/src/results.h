/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pybind11/pybind11.h>

#include <pcl/icf/verification/depth_verification.h>

namespace pcl_icf_python {

namespace py = pybind11;

/** \brief A types.SimpleNamespace holding \a fields (what every result is in Python). */
py::object makeNamespace(py::dict fields);

/** \brief The depth verification's terms (depth_verification.h) under the tool's JSON names. */
py::dict verificationDict(const pcl::icf::DepthExplanation& v);

}  // namespace pcl_icf_python
