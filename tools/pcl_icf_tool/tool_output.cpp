/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "tool_output.h"

#include <unistd.h>
#include <cerrno>
#include <filesystem>

namespace fs = std::filesystem;

namespace pcl_icf_tool {

bool samePath(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec))
    return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(fs::absolute(a), ec) == fs::weakly_canonical(fs::absolute(b), ec);
}

void checkOutputPath(const std::string& what, const std::string& output,
                     const std::vector<std::string>& inputs, bool force) {
  if (output.empty())
    throw OutputError(what + ": empty file name");
  for (const std::string& input : inputs)
    if (!input.empty() && samePath(output, input))
      throw OutputError(what + " " + output + " is an input file; refusing to overwrite it");
  std::error_code ec;
  const fs::path path(output);
  if (fs::is_directory(path, ec))
    throw OutputError(what + " " + output + " is a directory");
  if (fs::exists(path, ec) && !force)
    throw OutputError(what + " " + output + " exists; use --force to replace it");
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec))
    throw OutputError(what + " " + output + ": folder " + dir.string() + " does not exist");
  if (::access(dir.c_str(), W_OK) != 0)
    throw OutputError(what + " " + output + ": folder " + dir.string() + " is not writable");
}

void writeAtomically(const std::string& target, bool force,
                     const std::function<void(const std::string&)>& write) {
  const fs::path path(target);
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const fs::path temporary = dir / ("." + path.stem().string() + ".tmp-" +
                                    std::to_string(::getpid()) + path.extension().string());
  std::error_code ec;
  try {
    write(temporary.string());
  } catch (const std::exception& e) {
    fs::remove(temporary, ec);
    throw OutputError("could not write " + target + ": " + e.what());
  }
  if (!fs::exists(temporary, ec)) {
    throw OutputError("could not write " + target);
  }
  if (force) {
    fs::rename(temporary, path, ec);
    if (ec) {
      fs::remove(temporary, ec);
      throw OutputError("could not write " + target + ": " + ec.message());
    }
    return;
  }
  // link() fails when the target exists: no check-then-write race.
  if (::link(temporary.c_str(), path.c_str()) != 0) {
    const int err = errno;
    if (err == EEXIST) {
      fs::remove(temporary, ec);
      throw OutputError(target + " appeared while working; use --force to replace it");
    }
    // File systems without hard links: fall back to check + rename.
    if (fs::exists(path, ec)) {
      fs::remove(temporary, ec);
      throw OutputError(target + " exists; use --force to replace it");
    }
    fs::rename(temporary, path, ec);
    if (ec) {
      fs::remove(temporary, ec);
      throw OutputError("could not write " + target + ": " + ec.message());
    }
    return;
  }
  fs::remove(temporary, ec);
}

}  // namespace pcl_icf_tool
