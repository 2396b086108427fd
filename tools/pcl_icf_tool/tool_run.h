/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief pcl_icf_tool's run on one scene: the model and the scene read (units decided), the
 * localizer run, and what follows from its result (exit code, pose in scene units, posed
 * model, picture input). */

#include "tool_options.h"
#include "tool_render.h"

#include <pcl/PolygonMesh.h>
#include <pcl/icf/io/scene_io.h>
#include <pcl/icf/localization/object_localizer.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>

#include <chrono>
#include <stdexcept>
#include <string>

namespace pcl_icf_tool {

using Cloud = pcl::PointCloud<pcl::PointXYZRGBA>;
using Clock = std::chrono::steady_clock;

constexpr const char* kProgram = "pcl_icf_tool";

/** Bad input: a file that cannot be used. Exit code 2. */
class BadInput : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/** Milliseconds since \a start. */
double msSince(Clock::time_point start);
/** "pcl_icf_tool: warning: MESSAGE" on stderr. */
void warn(const std::string& message);
/** \a v with \a digits decimals. */
std::string fixed(double v, int digits);

/** The model as read and prepared. */
struct Model {
  std::string path;
  pcl::PolygonMesh mesh;  ///< as read, in the file's units
  Units units = Units::Metres;
  double metres_per_unit = 1.0;
  pcl::icf::IcfModel::ConstPtr icf;  ///< in metres
  double load_ms = 0.0, build_ms = 0.0;
  bool from_cache = false;          ///< read from the prepared-model cache, not built
  bool from_prepared_file = false;  ///< MODEL is a prepared-model file (--prepare's)
};

/** The prepared-model cache folder for \a options: "" with --no-cache, else
 * pcl::icf::defaultModelCacheFolder(). */
std::string cacheFolder(const ToolOptions& options);

/** What a model of \a metres_per_unit is prepared with (the library's defaults in metres). */
pcl::icf::IcfModelParams modelParams(double metres_per_unit);

/** --prepare MODEL -o FILE: the model prepared (or read from the cache) and written to FILE as
 * a prepared-model file, which MODEL arguments then take in milliseconds. Exit 0.
 * \throws BadInput, OutputError. */
int runPrepare(const ToolOptions& options);

/** Reads and prepares the model, through the prepared-model cache \a cache_folder ("" none);
 * --model-units auto decides mm or m from its extent. A prepared-model file (--prepare's)
 * is read as it is, with the mesh it holds. \throws BadInput for an unreadable file, an
 * unusable mesh, or a prepared file that does not fit (corrupt, other units or parameters). */
Model loadModel(const std::string& path, Units requested, bool quiet,
                const std::string& cache_folder);

/** The scene as read, and in metres. */
struct Scene {
  std::string path;
  Cloud::Ptr input;   ///< as read, in the file's units
  Cloud::Ptr metres;  ///< the same points in metres (the same object when the file is in m)
  pcl::icf::io::SceneFileInfo info;
  Units units = Units::Metres;
  double metres_per_unit = 1.0;
  double load_ms = 0.0;
};

/** Reads the scene; --units auto decides mm or m from its robust extent. A .png SCENE is a
 * depth image made a cloud in metres with \a png's camera (required). \throws BadInput. */
Scene loadScene(const std::string& path, Units requested, bool quiet,
                const DepthPngOptions& png = {});

/** The localizer's result on one scene and its wall time. */
struct Run {
  pcl::icf::localization::Localization loc;
  double ms = 0.0;
};

/** The localizer's parameters for \a scene: --camera in metres, the colour cue dropped, with a
 * warning, for a scene without colour. */
pcl::icf::localization::LocalizerParams localizerParams(const Scene& scene,
                                                        const ToolOptions& options, bool quiet);

/** The localizer on the scene in metres, with localizerParams. */
Run localize(const Scene& scene, const Model& model, const ToolOptions& options, bool quiet);

/** 0 found, 1 nothing accepted, 2 bad scene. */
int exitCode(const pcl::icf::localization::Localization& loc);

/** The object's pose in the scene's units: model (in scene units) -> scene. */
Eigen::Matrix4d scenePose(const pcl::icf::localization::ClusterLocalization& c,
                          double scene_metres_per_unit);

/** The rotation of \a pose as a unit quaternion with w >= 0. */
Eigen::Quaterniond quaternionOf(const Eigen::Matrix4d& pose);

/** Wall times of a run's stages (ms). */
struct Timing {
  double load_scene = 0, load_model = 0, build_model = 0, write = 0;
  Clock::time_point start = Clock::now();
};

/** One line for the picture: the model, the best cluster, its coverage, RMSE and score. */
std::string caption(const Model& model, const Run& run);

/** The posed model in the scene's units, or an empty mesh when nothing was found. */
pcl::PolygonMesh posedModel(const Scene& scene, const Model& model, const Run& run);

/** What reports call the models of \a paths: each file's name, with its place when two files
 * share one. */
std::vector<std::string> modelNames(const std::vector<std::string>& paths);

/** What renderPng and the viewer draw: the scene, the posed model, the caption. */
RenderInput renderInput(const Scene& scene, const ToolOptions& options,
                        const pcl::PolygonMesh& posed, const std::string& text);

}  // namespace pcl_icf_tool
