/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief pcl_icf_tool --track FRAMES MODEL...: the frames of a folder (name order) or a list
 * file followed with pcl::icf::tracking::ObjectTracker; one JSON line per frame on stdout,
 * progress on stderr; with --render-dir a picture per frame; with --follow the folder is
 * watched and each new frame tracked once it is completely written. */

#include "tool_options.h"

namespace pcl_icf_tool {

/** Tracks every model over the frames; returns the exit code as --batch does (2 when a frame
 * could not be used, else 1 when an object had no pose in some frame, else 0). A bad frame
 * (unreadable, another size or other units than the first good one) is reported by name and
 * the stream goes on. --follow: until no frame appeared for --idle-seconds (2 when none came).
 * \throws BadInput for a bad frame list or model, OutputError for a picture that may not be
 * written. */
int runTrack(const ToolOptions& options);

}  // namespace pcl_icf_tool
