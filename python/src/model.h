/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/PolygonMesh.h>
#include <pcl/icf/registration/icf_model.h>

#include <cstddef>
#include <string>

namespace pcl_icf_python {

/** \brief pcl_icf.Model: a prepared model and the scale its file was read at. */
struct Model {
  pcl::icf::IcfModel::ConstPtr icf;
  pcl::PolygonMesh mesh;  ///< as given, in its own units (Model.save writes it with the model)
  std::string units;      ///< "m" or "mm": the mesh's units
  std::size_t vertices = 0;
  std::string source = "built";  ///< "built", "cache" or "prepared file"
};

}  // namespace pcl_icf_python
