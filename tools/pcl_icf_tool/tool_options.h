/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief pcl_icf_tool's command line: the options, their parsing and the usage text. */

#include "common/arguments.h"

#include <pcl/icf/localization/object_localizer.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace pcl_icf_tool {

/** \brief Bad usage: an unknown option, a missing or nonsense value. Exit code 2. */
using UsageError = pcl_icf_tools::UsageError;

/** \brief Units of a scene or a mesh as given on the command line. */
enum class Units { Auto, Metres, Millimetres };

/** "m" / "mm" (Auto has no name of its own: "auto"). */
const char* unitsName(Units units);
/** Metres per unit: 1 or 0.001. */
double metresPerUnit(Units units);

/** \brief How a depth PNG SCENE becomes a cloud (BOP's depth images): --intrinsics,
 * --depth-scale, --rgb. */
struct DepthPngOptions {
  std::optional<Eigen::Vector4d> intrinsics;  ///< fx, fy, cx, cy (pixels)
  double depth_scale = 0.0;                   ///< millimetres per PNG unit (0: not given)
  std::string rgb;                            ///< the colour PNG of the same size ("" none)
};

/** \brief Everything pcl_icf_tool was asked to do. */
struct ToolOptions {
  bool help = false;
  bool list_fields = false;  ///< --list-fields: print the field registry
  std::string scene;         ///< SCENE (single mode)
  std::string model;         ///< MODEL
  /** --batch SCENES: a directory (every .pcd, .ply, .xyz, .asc in it, sorted) or a text file
   * listing scene paths (one a line, '#' comments, relative to the list's folder). */
  std::string batch;
  std::string out_dir;  ///< --out-dir (batch)
  /** --track FRAMES: a directory of frames (name order) or a list file, as --batch; every
   * positional argument is a MODEL to follow (tool_track). */
  std::string track;
  /** --track's MODELs; in single mode every MODEL after SCENE and --models LIST's, when more
   * than one object is asked for (tool_many). */
  std::vector<std::string> models;
  /** --models LIST's instance counts, one per entry of models (1 where not given). */
  std::vector<int> model_counts;
  std::string models_list;  ///< --models LIST: "MODEL [COUNT]" a line, '#' comments
  /** --render-dir DIR (track): DIR/NNNN_<frame>.png per frame, the tracked poses drawn. */
  std::string render_dir;
  /** --follow (track): FRAMES is a folder watched for new frames until --idle-seconds pass
   * without one. */
  bool follow = false;
  double idle_seconds = 10.0;  ///< --idle-seconds (follow)
  bool render_all = false;     ///< --render-all (batch): DIR/<scene>.png for every scene
  bool output_all = false;     ///< --output-all (batch): DIR/<scene>.ply for every found pose

  /** --camera: the camera's pose in the scene's frame, translation in the scene's units
   * (unset: the file's VIEWPOINT, the camera's frame by default). */
  std::optional<Eigen::Isometry3d> camera;
  DepthPngOptions depth_png;        ///< --intrinsics, --depth-scale, --rgb
  Units units = Units::Auto;        ///< --units
  Units model_units = Units::Auto;  ///< --model-units

  pcl::icf::localization::LocalizerParams params;  ///< everything the localizer gets
  std::string json;                                ///< --json FILE
  std::string output;                              ///< --output FILE.ply
  std::string render;                              ///< --render FILE.png
  int render_width = 0;  ///< --render-size WxH; 0: from the scene (see renderPng)
  int render_height = 0;
  Eigen::Vector3f render_colour{0.1f, 1.0f, 0.2f};  ///< --render-color, channels in [0, 1]
  bool view = false;                                ///< --view
  bool force = false;                               ///< --force
  /** --prepare MODEL -o FILE: MODEL prepared and written to FILE.icfmodel, nothing found. */
  std::string prepare;
  std::string prepare_output;  ///< -o FILE (--prepare)
  bool no_cache = false;       ///< --no-cache: prepare every model, read no cache, write none
  bool quiet = false;          ///< -q
  bool verbose = false;        ///< -v: PCL's and VTK's own messages too
};

/** \brief Parse argv. \throws UsageError with a one-line reason. Calls params.validate(). */
ToolOptions parseToolOptions(int argc, const char* const* argv);

/** \brief The usage text, in the style of PCL's tools; defaults printed from the code. */
std::string usageText(const std::string& program);

}  // namespace pcl_icf_tool
