/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief pcl_icf_tool --batch: every scene of a directory or list file against one model,
 * one JSON (and optionally PLY, PNG) per scene and a summary.json. */

#include "tool_options.h"

namespace pcl_icf_tool {

/** Runs the batch; returns the exit code (2 when a scene was unreadable, else 1 when one had
 * no accepted pose, else 0). \throws BadInput, OutputError before any work for a bad list or
 * an output that may not be written. */
int runBatch(const ToolOptions& options);

}  // namespace pcl_icf_tool
