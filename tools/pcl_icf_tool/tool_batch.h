/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief pcl_icf_tool --batch: every scene of a directory or list file against one model,
 * one JSON (and optionally PLY, PNG) per scene and a summary.json. */

#include "tool_options.h"

#include <string>
#include <vector>

namespace pcl_icf_tool {

/** Whether \a path names a scene file by its extension: .pcd, .ply, .xyz or .asc. */
bool isSceneFile(const std::string& path);

/** The scene files of \a source: a directory's .pcd, .ply, .xyz and .asc files in name order,
 * or the paths a list file names (one a line, '#' comments, relative to its folder).
 * \throws BadInput naming \a option for an empty directory, an unreadable or empty list. */
std::vector<std::string> listScenes(const std::string& source, const std::string& option);

/** Runs the batch; returns the exit code (2 when a scene was unreadable, else 1 when one had
 * no accepted pose, else 0). \throws BadInput, OutputError before any work for a bad list or
 * an output that may not be written. */
int runBatch(const ToolOptions& options);

}  // namespace pcl_icf_tool
