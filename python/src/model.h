/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/icf_model.h>

#include <cstddef>
#include <string>

namespace pcl_icf_python {

/** \brief pcl_icf.Model: a prepared model and the scale its file was read at. */
struct Model {
  pcl::icf::IcfModel::ConstPtr icf;
  std::string units;  ///< "m" or "mm": the mesh's units
  std::size_t vertices = 0;
};

}  // namespace pcl_icf_python
