/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief pcl_icf_tool SCENE MODEL MODEL... (or --models LIST): every object searched for in
 * one pass (localizeObjects), one report and one JSON document for the frame. */

#include "tool_options.h"

namespace pcl_icf_tool {

/** Runs the frame; 0 when any object was found, 1 when none, 2 for a bad scene (thrown as
 * BadInput). */
int runMany(const ToolOptions& options);

}  // namespace pcl_icf_tool
