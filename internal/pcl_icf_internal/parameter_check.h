/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Internal to the libraries' sources (not installed): the one way a params struct's
 * validate() reports a bad field, with PCL's "[pcl::icf::Class::method] " prefix:
 *
 *     [pcl::icf::AcceptanceParams::validate] max_rmse = -1: must be positive and finite
 *
 * Usage inside validate(): `const ParameterCheck fail("AcceptanceParams");` then
 * `fail("max_rmse", max_rmse, "must be positive and finite");` for each broken rule. */

#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace pcl {
namespace icf {
namespace internal {

class ParameterCheck {
 public:
  /** \a owner: the struct's name below pcl::icf ("AcceptanceParams",
   * "segmentation::ClusterParams"). */
  explicit ParameterCheck(std::string owner) : owner_(std::move(owner)) {}

  /** \throws std::invalid_argument "[pcl::icf::<owner>::validate] <field> = <value>: <rule>". */
  template <typename T>
  [[noreturn]] void operator()(const std::string& field, const T& value,
                               const std::string& rule) const {
    std::ostringstream msg;
    msg << "[pcl::icf::" << owner_ << "::validate] " << field << " = " << value << ": " << rule;
    throw std::invalid_argument(msg.str());
  }

 private:
  std::string owner_;
};

}  // namespace internal
}  // namespace icf
}  // namespace pcl
