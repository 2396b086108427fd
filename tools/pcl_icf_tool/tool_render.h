/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief pcl_icf_tool's pictures: an off-screen PNG from the camera's viewpoint and the
 * interactive viewer (thesis chapter 8). The only part of the project that links
 * pcl_visualization. Debian's VTK 9.1 renders through X only: a display is needed (Xvfb in CI,
 * see ensureDisplayOrReexec). */

#include <pcl/PolygonMesh.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace pcl_icf_tool {

/** \brief One model drawn at its pose, in the scene's units and frame. */
struct DrawnModel {
  pcl::PolygonMesh mesh;
  Eigen::Vector3f colour{0.1f, 1.0f, 0.2f};  ///< channels in [0, 1]
};

/** \brief One line of a picture's legend, written in its colour. */
struct LegendLine {
  std::string text;
  Eigen::Vector3f colour{1.0f, 1.0f, 1.0f};
};

/** \brief What a picture shows. Everything in the scene's units and frame. */
struct RenderInput {
  pcl::PointCloud<pcl::PointXYZRGBA>::ConstPtr scene;
  bool scene_has_colour = true;    ///< false: colour the scene by depth
  std::vector<DrawnModel> models;  ///< the models at their poses (none: the scene alone)
  std::vector<LegendLine> legend;  ///< lines at the bottom left (none: no legend)
  std::string caption;             ///< one line at the top left ("" for none)
  int width = 0;                   ///< 0: default (see renderPng)
  int height = 0;
};

/** \brief The colour of the \a k-th object in a picture of several: eight that tell apart on
 * a colour or depth-coloured scene, the tool's green first, then again from the start. */
Eigen::Vector3f objectColour(std::size_t k);

/** \brief True when an X display is named in DISPLAY. */
bool haveDisplay();

/** \brief When there is no display and \a need_render is set: re-executes this program under
 * `xvfb-run -a` (once; the environment marks the second run) and does not return on success.
 * Returns an error message ("" when nothing had to be done, or when already under xvfb-run)
 * when that is impossible: no xvfb-run on the PATH, or the exec failed. */
std::string ensureDisplayOrReexec(int argc, char** argv, bool need_render);

/** \brief Renders \a input from the scene's sensor pose (sensor_origin_, looking along the
 * sensor's +z with -y up: the Kinect frame) into a PNG at \a png_path. An organized scene is
 * drawn with the intrinsics its pixels imply (fitted), so the picture lines up with the
 * camera's image; default size: the organized size scaled to about 640 pixels wide, else
 * 800 x 600. \throws std::runtime_error when rendering fails or the picture is blank. */
void renderPng(const RenderInput& input, const std::string& png_path);

/** \brief Opens the interactive viewer on the same picture; clicking a point prints its
 * coordinates on stdout. Returns when the window is closed. */
void runViewer(const RenderInput& input);

}  // namespace pcl_icf_tool
