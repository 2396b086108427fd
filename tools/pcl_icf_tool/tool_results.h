/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief pcl_icf_tool's results: the JSON document, the console report, the posed model as
 * PLY and the picture as PNG, each written atomically. */

#include "tool_run.h"

#include <nlohmann/json.hpp>

#include <string>

namespace pcl_icf_tool {

using json = nlohmann::ordered_json;

/** One judged hypothesis as JSON: pose in the scene's units, confidence, the verification's
 * terms, alternatives, why refused. */
json clusterJson(const pcl::icf::localization::ClusterLocalization& c, int index,
                 const Scene& scene);

/** The run as JSON (doc/USER_GUIDE.md): inputs, status, every cluster, the best, timings. */
json resultJson(const Scene& scene, const Model& model, const ToolOptions& options, const Run& run,
                const Timing& timing);

/** The JSON of a scene that could not be read: status BadInput, exit code 2. */
json errorJson(const std::string& scene, const std::string& model, const std::string& error);

/** Writes \a j, numeric arrays on one line, atomically (see writeAtomically). */
void writeJson(const std::string& path, const json& j, bool force);

/** The human report on stdout: scene, model, table, clusters, best pose, time. */
void printReport(const Scene& scene, const Model& model, const Run& run, bool segment);

/** Writes the posed model as binary PLY, atomically. */
void writePly(const std::string& path, const pcl::PolygonMesh& mesh, bool force);

/** Renders \a input off-screen into a PNG, atomically. */
void writePng(const std::string& path, const RenderInput& input, bool force);

/** The picture of one scene as asked: written to --render (said unless -q), then shown with
 * --view (returns when the window is closed). */
void showPicture(const RenderInput& input, const ToolOptions& options);

}  // namespace pcl_icf_tool
