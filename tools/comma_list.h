/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace pcl_icf_tools {

/** \brief The non-empty items of a comma-separated option value: "a,,b" gives {"a", "b"}. */
inline std::vector<std::string> splitComma(const std::string& s) {
  std::vector<std::string> parts;
  std::stringstream in(s);
  std::string part;
  while (std::getline(in, part, ','))
    if (!part.empty())
      parts.push_back(part);
  return parts;
}

}  // namespace pcl_icf_tools
