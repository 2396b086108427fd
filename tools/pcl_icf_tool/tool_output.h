/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief pcl_icf_tool's files: safe output paths and atomic writes (the posed mesh written
 * through them: tool_mesh.h). */

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace pcl_icf_tool {

/** \brief An output that must not or cannot be written. Exit code 2. */
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/** \brief True when \a a and \a b name the same file (or would, once created). */
bool samePath(const std::string& a, const std::string& b);

/** \brief Checks, before any work is done, that \a output may be written: it is not one of
 * \a inputs (never, even with \a force), it does not exist unless \a force, it is not a
 * directory, and its folder exists and is writable. \throws OutputError with a one-line
 * reason naming \a what ("--json", ...). */
void checkOutputPath(const std::string& what, const std::string& output,
                     const std::vector<std::string>& inputs, bool force);

/** \brief Writes \a target atomically: \a write fills a temporary file in the same folder
 * (same extension), which then replaces \a target by rename (with \a force) or is linked to it
 * only if \a target still does not exist (without). Nothing is left behind on failure.
 * \throws OutputError when \a write throws or the file cannot be committed. */
void writeAtomically(const std::string& target, bool force,
                     const std::function<void(const std::string& temporary)>& write);

}  // namespace pcl_icf_tool
