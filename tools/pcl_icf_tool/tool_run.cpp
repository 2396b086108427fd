/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "tool_run.h"

#include <pcl/icf/registration/model_file.h>

#include "tool_mesh.h"
#include "tool_output.h"

#include <pcl/icf/io/bop_dataset.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/registration/face_mesh.h>
#include <pcl/icf/segmentation/finite_indices.h>
#include <pcl/icf/segmentation/scene_extent.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

namespace pcl_icf_tool {

namespace fs = std::filesystem;
namespace localization = pcl::icf::localization;
namespace seg = pcl::icf::segmentation;

namespace {

/** --units auto: a scene whose finite points span more than this (robustExtent: stray points
 * left out) is in millimetres. */
constexpr double kSceneMillimetreExtent = 20.0;
/** --model-units auto: a mesh that spans more than this beside a metre scene is in mm. */
constexpr double kModelMillimetreExtent = 2.0;

}  // namespace

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void warn(const std::string& message) {
  std::fprintf(stderr, "%s: warning: %s\n", kProgram, message.c_str());
}

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

std::string cacheFolder(const ToolOptions& options) {
  return options.no_cache ? std::string() : pcl::icf::defaultModelCacheFolder();
}

pcl::icf::IcfModelParams modelParams(double metres_per_unit) {
  pcl::icf::IcfModelParams params;
  params.mesh.scale = static_cast<float>(metres_per_unit);
  return params;
}

namespace {

/** The mesh of \a path: a mesh file, or the mesh a prepared-model file holds. */
pcl::PolygonMesh readMesh(const std::string& path, bool prepared) {
  try {
    return prepared ? pcl::icf::readModelFileMesh(path) : pcl::icf::io::loadPolygonMesh(path);
  } catch (const pcl::icf::io::FileError& e) {
    throw BadInput(e.what());
  } catch (const pcl::icf::ModelFileError& e) {
    throw BadInput(e.what());
  }
}

/** The model of \a m's mesh: read from its prepared file, or through the cache. */
void prepareModel(Model& m, const std::string& cache_folder, bool quiet) {
  const pcl::icf::IcfModelParams params = modelParams(m.metres_per_unit);
  if (m.from_prepared_file) {
    try {
      m.icf = pcl::icf::readModelFile(m.path, m.mesh, params);
    } catch (const pcl::icf::ModelFileError& e) {
      const std::string what = e.what();
      throw BadInput(what + (what.find("other parameters") == std::string::npos
                                 ? std::string()
                                 : ": prepared in other units (give the --model-units it was "
                                   "prepared with) or by another version (prepare it again with "
                                   "--prepare)"));
    }
    return;
  }
  const pcl::icf::CachedModel cached = pcl::icf::buildModelCached(m.mesh, params, cache_folder);
  if (!cached.warning.empty() && !quiet)
    warn(m.path + ": prepared-model cache: " + cached.warning);
  m.icf = cached.model;
  m.from_cache = cached.from_cache;
}

}  // namespace

Model loadModel(const std::string& path, Units requested, bool quiet,
                const std::string& cache_folder) {
  Model m;
  m.path = path;
  m.from_prepared_file = pcl::icf::isModelFile(path);
  const auto start = Clock::now();
  m.mesh = readMesh(path, m.from_prepared_file);
  m.load_ms = msSince(start);
  if (m.mesh.polygons.empty())
    throw BadInput(path + ": the mesh has no faces (a point cloud is not a model)");
  m.units = requested;
  if (requested == Units::Auto) {
    const double extent = pcl_icf_tool::meshExtent(m.mesh);
    m.units = extent > kModelMillimetreExtent ? Units::Millimetres : Units::Metres;
    if (m.units == Units::Millimetres && !quiet)
      warn(path + " spans " + fixed(extent, 1) +
           " units, too large for metres: read as millimetres (--model-units m to override)");
  }
  m.metres_per_unit = pcl_icf_tool::metresPerUnit(m.units);
  const auto build = Clock::now();
  try {
    prepareModel(m, cache_folder, quiet);
  } catch (const pcl::icf::InvalidMeshError& e) {
    throw BadInput(path + ": not a usable model: " + e.what());
  } catch (const std::invalid_argument& e) {
    throw BadInput(path + ": not a usable model: " + e.what());
  }
  m.build_ms = msSince(build);
  return m;
}

int runPrepare(const ToolOptions& options) {
  checkOutputPath("-o", options.prepare_output, {options.prepare}, options.force);
  if (pcl::icf::io::fileExtension(options.prepare_output) != "icfmodel")
    throw OutputError("-o " + options.prepare_output +
                      ": a prepared model is written as .icfmodel");
  const Model m =
      loadModel(options.prepare, options.model_units, options.quiet, cacheFolder(options));
  const std::string key = pcl::icf::preparationKey(m.mesh, modelParams(m.metres_per_unit));
  try {
    pcl::icf::writeModelFile(*m.icf, m.mesh, key, options.prepare_output);
  } catch (const pcl::icf::ModelFileError& e) {
    throw OutputError(e.what());
  }
  if (!options.quiet)
    std::printf(
        "prepared %s (%zu faces, %s, %s) in %.0f ms\nwrote  %s\n", options.prepare.c_str(),
        m.mesh.polygons.size(), unitsName(m.units),
        m.from_prepared_file ? "from a prepared file" : (m.from_cache ? "from the cache" : "built"),
        m.build_ms, options.prepare_output.c_str());
  return 0;
}

namespace {

/** A depth PNG SCENE as a cloud in metres (readBopDepthImage) with its file's information. */
Cloud::Ptr readDepthPng(const std::string& path, const DepthPngOptions& png,
                        pcl::icf::io::SceneFileInfo& info) {
  if (!png.intrinsics || !(png.depth_scale > 0.0))
    throw BadInput(path +
                   ": a depth image needs its camera: --intrinsics FX,FY,CX,CY and "
                   "--depth-scale S (millimetres per unit)");
  pcl::icf::io::BopCamera camera;
  const Eigen::Vector4d& k = *png.intrinsics;
  camera.K << k[0], 0, k[2], 0, k[1], k[3], 0, 0, 1;
  camera.depth_scale = png.depth_scale;
  Cloud::Ptr cloud = pcl::icf::io::readBopDepthImage(path, camera, png.rgb);
  info.format = "png";
  info.has_colour = !png.rgb.empty();
  info.organized = true;
  info.points = cloud->size();
  info.finite_points = 0;
  for (const auto& p : *cloud)
    info.finite_points += std::isfinite(p.z);
  if (info.finite_points == 0)
    throw BadInput(path + ": the depth image holds no depth");
  return cloud;
}

}  // namespace

Scene loadScene(const std::string& path, Units requested, bool quiet, const DepthPngOptions& png) {
  Scene s;
  s.path = path;
  const bool depth_image = pcl::icf::io::fileExtension(path) == "png";
  if (depth_image && requested != Units::Auto)
    throw BadInput("--units is not for a depth image SCENE: " + path +
                   " becomes a cloud in metres (its unit is --depth-scale)");
  if (!depth_image && (png.intrinsics || png.depth_scale > 0.0 || !png.rgb.empty()))
    throw BadInput(
        "--intrinsics, --depth-scale and --rgb are for a depth image SCENE (.png), "
        "not " +
        path);
  const auto start = Clock::now();
  try {
    s.input =
        depth_image ? readDepthPng(path, png, s.info) : pcl::icf::io::loadSceneCloud(path, &s.info);
  } catch (const pcl::icf::io::FileError& e) {
    throw BadInput(e.what());
  }
  s.load_ms = msSince(start);
  s.units = depth_image ? Units::Metres : requested;
  if (s.units == Units::Auto) {
    // Without stray points: one corrupt return must not make a metre scene look like mm.
    const double extent = seg::robustExtent(*s.input, seg::finiteIndices(*s.input));
    s.units = extent > kSceneMillimetreExtent ? Units::Millimetres : Units::Metres;
    if (s.units == Units::Millimetres && !quiet)
      warn(path + " spans " + fixed(extent, 1) +
           " units, too large for metres: read as millimetres (--units m to override)");
  }
  s.metres_per_unit = pcl_icf_tool::metresPerUnit(s.units);
  if (s.metres_per_unit == 1.0) {
    s.metres = s.input;
  } else {
    s.metres = pcl::make_shared<Cloud>(*s.input);
    const float k = static_cast<float>(s.metres_per_unit);
    for (auto& q : *s.metres) {
      q.x *= k;
      q.y *= k;
      q.z *= k;
    }
    s.metres->sensor_origin_.head<3>() *= k;
  }
  return s;
}

localization::LocalizerParams localizerParams(const Scene& scene, const ToolOptions& options,
                                              bool quiet) {
  localization::LocalizerParams params = options.params;
  if (params.colour.expected && !scene.info.has_colour) {
    if (!quiet)
      warn(scene.path + " has no colour: --color is ignored");
    params.colour.expected.reset();
  }
  if (options.camera) {
    Eigen::Isometry3d camera = *options.camera;
    camera.translation() *= scene.metres_per_unit;
    params.camera_pose = camera.cast<float>();
  }
  return params;
}

Run localize(const Scene& scene, const Model& model, const ToolOptions& options, bool quiet) {
  const localization::LocalizerParams params = localizerParams(scene, options, quiet);
  Run run;
  const auto start = Clock::now();
  run.loc = localization::localizeObject(*scene.metres, *model.icf, params);
  run.ms = msSince(start);
  return run;
}

int exitCode(const localization::Localization& loc) {
  switch (loc.status) {
    case localization::LocalizationStatus::Found:
      return 0;
    case localization::LocalizationStatus::BadScene:
      return 2;
    default:
      return 1;
  }
}

Eigen::Matrix4d scenePose(const localization::ClusterLocalization& c,
                          double scene_metres_per_unit) {
  Eigen::Matrix4d pose = c.icf.object_pose.cast<double>();
  pose.topRightCorner<3, 1>() /= scene_metres_per_unit;
  return pose;
}

Eigen::Quaterniond quaternionOf(const Eigen::Matrix4d& pose) {
  Eigen::Quaterniond q(Eigen::Matrix3d(pose.topLeftCorner<3, 3>()));
  q.normalize();
  if (q.w() < 0.0)
    q.coeffs() = -q.coeffs();
  return q;
}

std::string caption(const Model& model, const Run& run) {
  const std::string name = fs::path(model.path).filename().string();
  if (run.loc.best < 0)
    return name + ": not found (" + localization::toString(run.loc.status) + ")";
  const auto& c = run.loc.clusters[static_cast<std::size_t>(run.loc.best)];
  return name + ": cluster " + std::to_string(run.loc.best) + ", coverage " +
         fixed(c.icf.quality.surface_coverage, 2) + ", rmse " + fixed(1e3 * c.icf.quality.rmse, 1) +
         " mm, score " + fixed(c.score, 2);
}

pcl::PolygonMesh posedModel(const Scene& scene, const Model& model, const Run& run) {
  if (run.loc.best < 0)
    return {};
  const auto& c = run.loc.clusters[static_cast<std::size_t>(run.loc.best)];
  return pcl_icf_tool::posedMesh(model.mesh, scenePose(c, scene.metres_per_unit),
                                 model.metres_per_unit / scene.metres_per_unit);
}

std::vector<std::string> modelNames(const std::vector<std::string>& paths) {
  std::vector<std::string> names;
  for (const auto& p : paths)
    names.push_back(fs::path(p).filename().string());
  for (std::size_t a = 0; a < names.size(); ++a)
    for (std::size_t b = a + 1; b < names.size(); ++b)
      if (names[a] == names[b]) {
        for (std::size_t k = 0; k < names.size(); ++k)
          names[k] += " #" + std::to_string(k);
        return names;
      }
  return names;
}

RenderInput renderInput(const Scene& scene, const ToolOptions& options,
                        const pcl::PolygonMesh& posed, const std::string& text) {
  RenderInput in;
  in.scene = scene.input;
  in.scene_has_colour = scene.info.has_colour;
  if (!posed.polygons.empty())
    in.models.push_back({posed, options.render_colour});
  in.caption = text;
  in.width = options.render_width;
  in.height = options.render_height;
  return in;
}

}  // namespace pcl_icf_tool
