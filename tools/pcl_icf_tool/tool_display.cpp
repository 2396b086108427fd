/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// haveDisplay() on its own: Xlib's macros (None, Status, Bool, ...) stay out of the files that
// include VTK and PCL.
#include "tool_render.h"

#include <X11/Xlib.h>

#include <cstdlib>

namespace pcl_icf_tool {

bool haveDisplay() {
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
    return false;
  // VTK aborts the process on a display it cannot open: try it first. The connection stays
  // open for the life of the process: an X server without -noreset (xvfb-run's default)
  // resets when its last client leaves, and a connection made during the reset fails (VTK
  // would then abort).
  static Display* probe = XOpenDisplay(nullptr);
  return probe != nullptr;
}

}  // namespace pcl_icf_tool
