/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// pcl_icf_tool: find a CAD mesh's 6D pose in a depth scan (doc/USER_GUIDE.md).
//   pcl_icf_tool SCENE MODEL [options]
//   pcl_icf_tool --batch SCENES MODEL --out-dir DIR [options]
// Segments the table, localises the model in every cluster, prints the clusters and the best
// pose, and writes on request the result as JSON, the posed model as PLY and a picture.
// Exit codes: 0 object found, 1 nothing accepted, 2 bad usage or bad input.
#include "tool_options.h"
#include "tool_output.h"
#include "tool_render.h"

#include <pcl/console/print.h>
#include <pcl/icf/face_mesh.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/io/scene_io.h>
#include <pcl/icf/segmentation/object_localizer.h>
#include <pcl/io/ply_io.h>

#include <vtkObject.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

namespace {

namespace fs = std::filesystem;
namespace seg = pcl::icf::segmentation;
using pcl_icf_tool::OutputError;
using pcl_icf_tool::ToolOptions;
using pcl_icf_tool::Units;
using Cloud = pcl::PointCloud<pcl::PointXYZRGBA>;
using Clock = std::chrono::steady_clock;
using json = nlohmann::ordered_json;

constexpr const char* kProgram = "pcl_icf_tool";
/** --units auto: a scene whose finite points span more than this is in millimetres. */
constexpr double kSceneMillimetreExtent = 20.0;
/** --model-units auto: a mesh that spans more than this beside a metre scene is in mm. */
constexpr double kModelMillimetreExtent = 2.0;

/** Bad input: a file that cannot be used. Exit code 2. */
class BadInput : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

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

// ---------------------------------------------------------------------------------------------
// Inputs

struct Model {
  std::string path;
  pcl::PolygonMesh mesh;  ///< as read, in the file's units
  Units units = Units::Metres;
  double metres_per_unit = 1.0;
  pcl::icf::IcfModel::ConstPtr icf;  ///< in metres
  double load_ms = 0.0, build_ms = 0.0;
};

Model loadModel(const std::string& path, Units requested, bool quiet) {
  Model m;
  m.path = path;
  const auto start = Clock::now();
  try {
    m.mesh = pcl::icf::io::loadPolygonMesh(path);
  } catch (const pcl::icf::io::FileError& e) {
    throw BadInput(e.what());
  }
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
  pcl::icf::IcfModelParams params;
  params.mesh.scale = static_cast<float>(m.metres_per_unit);
  try {
    m.icf = pcl::icf::IcfModel::build(m.mesh, params);
  } catch (const pcl::icf::InvalidMeshError& e) {
    throw BadInput(path + ": not a usable model: " + e.what());
  } catch (const std::invalid_argument& e) {
    throw BadInput(path + ": not a usable model: " + e.what());
  }
  m.build_ms = msSince(build);
  return m;
}

struct Scene {
  std::string path;
  Cloud::Ptr input;   ///< as read, in the file's units
  Cloud::Ptr metres;  ///< the same points in metres (the same object when the file is in m)
  pcl::icf::io::SceneFileInfo info;
  Units units = Units::Metres;
  double metres_per_unit = 1.0;
  double load_ms = 0.0;
};

Scene loadScene(const std::string& path, Units requested, bool quiet) {
  Scene s;
  s.path = path;
  const auto start = Clock::now();
  try {
    s.input = pcl::icf::io::loadSceneCloud(path, &s.info);
  } catch (const pcl::icf::io::FileError& e) {
    throw BadInput(e.what());
  }
  s.load_ms = msSince(start);
  s.units = requested;
  if (requested == Units::Auto) {
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
    Eigen::Vector3f hi = -lo;
    for (const auto& q : *s.input)
      if (std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z)) {
        lo = lo.cwiseMin(q.getVector3fMap());
        hi = hi.cwiseMax(q.getVector3fMap());
      }
    const double extent = (hi - lo).norm();
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

// ---------------------------------------------------------------------------------------------
// Localisation

struct Run {
  seg::Localization loc;
  double ms = 0.0;
};

Run localize(const Scene& scene, const Model& model, const ToolOptions& options, bool quiet) {
  seg::LocalizerParams params = options.params;
  if (params.colour.expected && !scene.info.has_colour) {
    if (!quiet)
      warn(scene.path + " has no colour: --color is ignored");
    params.colour.expected.reset();
  }
  Run run;
  const auto start = Clock::now();
  run.loc = seg::localizeObject(*scene.metres, *model.icf, params);
  run.ms = msSince(start);
  return run;
}

int exitCode(const seg::Localization& loc) {
  switch (loc.status) {
    case seg::LocalizationStatus::Found:
      return 0;
    case seg::LocalizationStatus::BadScene:
      return 2;
    default:
      return 1;
  }
}

/** The object's pose in the scene's units: model (in scene units) -> scene. */
Eigen::Matrix4d scenePose(const seg::ClusterLocalization& c, double scene_metres_per_unit) {
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

// ---------------------------------------------------------------------------------------------
// JSON

json clusterJson(const seg::ClusterLocalization& c, int index, const Scene& scene) {
  const Eigen::Matrix4d pose = scenePose(c, scene.metres_per_unit);
  const Eigen::Quaterniond q = quaternionOf(pose);
  json rows = json::array();
  for (int r = 0; r < 4; ++r)
    rows.push_back({pose(r, 0), pose(r, 1), pose(r, 2), pose(r, 3)});
  json j;
  j["cluster"] = index;
  j["points"] = c.indices.indices.size();
  j["pose"] = rows;
  j["quaternion_wxyz"] = {q.w(), q.x(), q.y(), q.z()};
  j["translation"] = {pose(0, 3), pose(1, 3), pose(2, 3)};
  j["score"] = c.score;
  j["inlier_ratio"] = c.icf.quality.inlier_ratio;
  j["rmse"] = c.icf.quality.rmse / scene.metres_per_unit;
  j["surface_coverage"] = c.icf.quality.surface_coverage;
  j["accepted"] = c.accepted;
  j["method"] = c.icf.method;
  j["fallback_ran"] = c.icf.fallback_ran;
  j["icf_status"] = pcl::icf::toString(c.icf.status);
  j["reason"] = c.reason;
  j["gate_far_points"] = c.gate_far_points;
  j["free_space_violation"] = c.free_space_violation;
  j["colour_similarity"] = c.colour_similarity ? json(*c.colour_similarity) : json(nullptr);
  j["time_ms"] = c.icf.time_ms;
  return j;
}

struct Timing {
  double load_scene = 0, load_model = 0, build_model = 0, write = 0;
  Clock::time_point start = Clock::now();
};

json resultJson(const Scene& scene, const Model& model, const ToolOptions& options, const Run& run,
                const Timing& timing) {
  json j;
  j["scene"] = scene.path;
  j["model"] = model.path;
  j["units"] = pcl_icf_tool::unitsName(scene.units);
  j["model_units"] = pcl_icf_tool::unitsName(model.units);
  j["seed"] = options.params.icf.seed;
  j["strategy"] = pcl::icf::toString(options.params.icf.strategy);
  j["fallback"] = pcl::icf::toString(options.params.icf.fallback);
  j["segment"] = options.params.segment;
  j["status"] = seg::toString(run.loc.status);
  j["message"] = run.loc.message;
  j["exit_code"] = exitCode(run.loc);
  j["best"] = nullptr;
  json clusters = json::array();
  for (std::size_t k = 0; k < run.loc.clusters.size(); ++k)
    clusters.push_back(clusterJson(run.loc.clusters[k], static_cast<int>(k), scene));
  if (run.loc.best >= 0)
    j["best"] = clusters[static_cast<std::size_t>(run.loc.best)];
  j["clusters"] = clusters;
  j["scene_info"] = {{"format", scene.info.format},
                     {"width", scene.input->width},
                     {"height", scene.input->height},
                     {"organized", scene.info.organized},
                     {"has_colour", scene.info.has_colour},
                     {"points", scene.info.points},
                     {"finite_points", scene.info.finite_points}};
  j["model_info"] = {
      {"vertices", static_cast<std::size_t>(model.mesh.cloud.width) * model.mesh.cloud.height},
      {"faces", model.icf->mesh().size()},
      {"radius", model.icf->radius() / scene.metres_per_unit}};
  j["timing_ms"] = {
      {"load_scene", timing.load_scene},         {"load_model", timing.load_model},
      {"build_model", timing.build_model},       {"segmentation", run.loc.segmentation_ms},
      {"registration", run.loc.registration_ms}, {"localization", run.ms},
      {"total", msSince(timing.start)}};
  return j;
}

json errorJson(const std::string& scene, const std::string& model, const std::string& error) {
  json j;
  j["scene"] = scene;
  j["model"] = model;
  j["status"] = "BadInput";
  j["message"] = error;
  j["exit_code"] = 2;
  j["best"] = nullptr;
  j["clusters"] = json::array();
  return j;
}

/** j.dump(2) with every array of numbers on one line ("pose": [[r00, r01, ...], ...]). A '['
 * followed by a line break is never inside a JSON string, so strings are left alone. */
std::string prettyJson(const json& j) {
  const std::string text = j.dump(2);
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '[' && i + 1 < text.size() && text[i + 1] == '\n') {
      const std::size_t close = text.find(']', i);
      const std::string body =
          close == std::string::npos ? std::string() : text.substr(i + 1, close - i - 1);
      if (!body.empty() && body.find_first_not_of("0123456789+-.eE, \n") == std::string::npos) {
        out += '[';
        bool space = false;
        for (const char c : body) {
          if (c == ' ' || c == '\n') {
            space = true;
            continue;
          }
          if (space && out.back() == ',')
            out += ' ';
          space = false;
          out += c;
        }
        out += ']';
        i = close;
        continue;
      }
    }
    out += text[i];
  }
  return out;
}

void writeJson(const std::string& path, const json& j, bool force) {
  pcl_icf_tool::writeAtomically(path, force, [&](const std::string& tmp) {
    std::ofstream out(tmp);
    out << prettyJson(j) << "\n";
    out.close();
    if (!out)
      throw std::runtime_error("write error");
  });
}

// ---------------------------------------------------------------------------------------------
// Report

void printReport(const Scene& scene, const Model& model, const Run& run, bool segment) {
  const auto& loc = run.loc;
  const char* units = pcl_icf_tool::unitsName(scene.units);
  std::printf("scene  %s: %u x %u%s, %zu finite points, %s%s\n", scene.path.c_str(),
              scene.input->width, scene.input->height, scene.info.organized ? " organized" : "",
              scene.info.finite_points, units, scene.info.has_colour ? ", colour" : "");
  std::printf("model  %s: %zu faces, radius %s %s (%s)\n", model.path.c_str(),
              model.icf->mesh().size(),
              fixed(model.icf->radius() / scene.metres_per_unit, 3).c_str(), units,
              pcl_icf_tool::unitsName(model.units));
  if (segment)
    std::printf("table  %s, %zu plane points, %zu clusters above it, %zu candidates tried\n",
                seg::toString(loc.segmentation.status), loc.segmentation.plane.inliers.size(),
                loc.segmentation.clusters.size(), loc.clusters.size());
  if (!loc.clusters.empty()) {
    std::printf("\n  #  points   score  coverage  inliers  rmse[mm]  result\n");
    for (std::size_t k = 0; k < loc.clusters.size(); ++k) {
      const auto& c = loc.clusters[k];
      std::printf("%3zu %7zu  %6.3f %9.3f %8.3f %9.2f  %s%s\n", k, c.indices.indices.size(),
                  c.score, c.icf.quality.surface_coverage, c.icf.quality.inlier_ratio,
                  1e3 * c.icf.quality.rmse, static_cast<int>(k) == loc.best ? "BEST, " : "",
                  c.accepted ? "accepted" : ("rejected: " + c.reason).c_str());
    }
  }
  std::printf("\n");
  if (loc.best < 0) {
    std::printf("no object found: %s (%s)\n", seg::toString(loc.status), loc.message.c_str());
    if (segment && loc.status == seg::LocalizationStatus::NoClusters)
      std::printf("       (for a cloud that holds one object, use --no-segment)\n");
  } else {
    const auto& c = loc.clusters[static_cast<std::size_t>(loc.best)];
    const Eigen::Matrix4d pose = scenePose(c, scene.metres_per_unit);
    const Eigen::Quaterniond q = quaternionOf(pose);
    std::printf("best   cluster %d by %s, score %.3f\n", loc.best, c.icf.method.c_str(), c.score);
    std::printf("pose   model -> scene, %s:\n", units);
    for (int r = 0; r < 4; ++r)
      std::printf("       %10.6f %10.6f %10.6f %12.6f\n", pose(r, 0), pose(r, 1), pose(r, 2),
                  pose(r, 3));
    std::printf("quaternion wxyz  %.6f %.6f %.6f %.6f\n", q.w(), q.x(), q.y(), q.z());
    std::printf("translation      %.6f %.6f %.6f %s\n", pose(0, 3), pose(1, 3), pose(2, 3), units);
  }
  std::printf("time   %.0f ms (segmentation %.0f, registration %.0f)\n", run.ms,
              loc.segmentation_ms, loc.registration_ms);
}

std::string caption(const Scene& scene, const Model& model, const Run& run) {
  const std::string name = fs::path(model.path).filename().string();
  if (run.loc.best < 0)
    return name + ": not found (" + seg::toString(run.loc.status) + ")";
  const auto& c = run.loc.clusters[static_cast<std::size_t>(run.loc.best)];
  (void)scene;
  return name + ": cluster " + std::to_string(run.loc.best) + ", coverage " +
         fixed(c.icf.quality.surface_coverage, 2) + ", rmse " + fixed(1e3 * c.icf.quality.rmse, 1) +
         " mm, score " + fixed(c.score, 2);
}

/** The posed model in the scene's units, or an empty mesh when nothing was found. */
pcl::PolygonMesh posedModel(const Scene& scene, const Model& model, const Run& run) {
  if (run.loc.best < 0)
    return {};
  const auto& c = run.loc.clusters[static_cast<std::size_t>(run.loc.best)];
  return pcl_icf_tool::posedMesh(model.mesh, scenePose(c, scene.metres_per_unit),
                                 model.metres_per_unit / scene.metres_per_unit);
}

void writePly(const std::string& path, const pcl::PolygonMesh& mesh, bool force) {
  pcl_icf_tool::writeAtomically(path, force, [&](const std::string& tmp) {
    if (pcl::io::savePLYFileBinary(tmp, mesh) < 0)
      throw std::runtime_error("PCL's PLY writer failed");
  });
}

void writePng(const std::string& path, const pcl_icf_tool::RenderInput& input, bool force) {
  pcl_icf_tool::writeAtomically(
      path, force, [&](const std::string& tmp) { pcl_icf_tool::renderPng(input, tmp); });
}

pcl_icf_tool::RenderInput renderInput(const Scene& scene, const ToolOptions& options,
                                      const pcl::PolygonMesh& posed, const std::string& text) {
  pcl_icf_tool::RenderInput in;
  in.scene = scene.input;
  in.scene_has_colour = scene.info.has_colour;
  in.posed_model = posed.polygons.empty() ? nullptr : &posed;
  in.model_colour = options.render_colour;
  in.caption = text;
  in.width = options.render_width;
  in.height = options.render_height;
  return in;
}

// ---------------------------------------------------------------------------------------------
// One scene

/** Everything a single run would refuse to write, checked before any work. */
void checkSingleOutputs(const ToolOptions& options) {
  const std::vector<std::string> inputs = {options.scene, options.model};
  if (!options.json.empty())
    pcl_icf_tool::checkOutputPath("--json", options.json, inputs, options.force);
  if (!options.output.empty())
    pcl_icf_tool::checkOutputPath("--output", options.output, inputs, options.force);
  if (!options.render.empty())
    pcl_icf_tool::checkOutputPath("--render", options.render, inputs, options.force);
  const std::vector<std::string> outs = {options.json, options.output, options.render};
  for (std::size_t a = 0; a < outs.size(); ++a)
    for (std::size_t b = a + 1; b < outs.size(); ++b)
      if (!outs[a].empty() && !outs[b].empty() && pcl_icf_tool::samePath(outs[a], outs[b]))
        throw OutputError("two outputs name the same file " + outs[a]);
  if (!options.output.empty() && pcl::icf::io::fileExtension(options.output) != "ply")
    throw OutputError("--output " + options.output + ": the posed model is written as .ply");
  if (!options.render.empty() && pcl::icf::io::fileExtension(options.render) != "png")
    throw OutputError("--render " + options.render + ": the picture is written as .png");
}

int runSingle(const ToolOptions& options) {
  Timing timing;
  const bool quiet = options.quiet;
  const Scene scene = loadScene(options.scene, options.units, quiet);
  timing.load_scene = scene.load_ms;
  const Model model = loadModel(options.model, options.model_units, quiet);
  timing.load_model = model.load_ms;
  timing.build_model = model.build_ms;

  const Run run = localize(scene, model, options, quiet);
  const int code = exitCode(run.loc);
  if (code == 2)
    throw BadInput(options.scene + ": " + run.loc.message +
                   (options.params.segment ? " (for a cloud that holds one object, use "
                                             "--no-segment)"
                                           : ""));
  if (!quiet)
    printReport(scene, model, run, options.params.segment);

  const pcl::PolygonMesh posed = posedModel(scene, model, run);
  if (!options.json.empty()) {
    writeJson(options.json, resultJson(scene, model, options, run, timing), options.force);
    if (!quiet)
      std::printf("wrote  %s\n", options.json.c_str());
  }
  if (!options.output.empty()) {
    if (posed.polygons.empty()) {
      if (!quiet)
        std::printf("no pose: %s not written\n", options.output.c_str());
    } else {
      writePly(options.output, posed, options.force);
      if (!quiet)
        std::printf("wrote  %s\n", options.output.c_str());
    }
  }
  const auto input = renderInput(scene, options, posed, caption(scene, model, run));
  if (!options.render.empty()) {
    writePng(options.render, input, options.force);
    if (!quiet)
      std::printf("wrote  %s\n", options.render.c_str());
  }
  std::fflush(stdout);
  if (options.view)
    pcl_icf_tool::runViewer(input);
  return code;
}

// ---------------------------------------------------------------------------------------------
// Batch

bool isSceneFile(const fs::path& p) {
  const std::string ext = pcl::icf::io::fileExtension(p.string());
  return ext == "pcd" || ext == "ply" || ext == "xyz" || ext == "asc";
}

std::vector<std::string> listScenes(const std::string& source) {
  std::vector<std::string> scenes;
  std::error_code ec;
  if (fs::is_directory(source, ec)) {
    for (const auto& entry : fs::directory_iterator(source, ec))
      if (entry.is_regular_file(ec) && isSceneFile(entry.path()))
        scenes.push_back(entry.path().string());
    std::sort(scenes.begin(), scenes.end());
    if (scenes.empty())
      throw BadInput(source + ": no .pcd, .ply, .xyz or .asc file in this directory");
    return scenes;
  }
  try {
    pcl::icf::io::requireReadableFile(source);
  } catch (const pcl::icf::io::FileError& e) {
    throw BadInput(std::string(e.what()) + " (--batch takes a directory or a list file)");
  }
  std::ifstream in(source);
  const fs::path base = fs::path(source).parent_path();
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r')
      line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#')
      continue;
    const auto last = line.find_last_not_of(" \t");
    const fs::path p(line.substr(first, last - first + 1));
    if (line.find('\0') != std::string::npos || line.size() > 4096)
      throw BadInput(source + ":" + std::to_string(number) + ": not a file name");
    scenes.push_back((p.is_absolute() ? p : base / p).string());
  }
  if (scenes.empty())
    throw BadInput(source + ": the list names no scene");
  return scenes;
}

/** Output base names: the scene's stem, or its file name where stems collide, made unique. */
std::vector<std::string> outputNames(const std::vector<std::string>& scenes) {
  std::map<std::string, int> stems;
  for (const auto& s : scenes)
    ++stems[fs::path(s).stem().string()];
  std::vector<std::string> names;
  std::set<std::string> used;
  for (const auto& s : scenes) {
    std::string name = fs::path(s).stem().string();
    if (stems[name] > 1)
      name = fs::path(s).filename().string();
    std::string unique = name;
    for (int k = 2; used.count(unique); ++k)
      unique = name + "_" + std::to_string(k);
    used.insert(unique);
    names.push_back(unique);
  }
  return names;
}

class Progress {
 public:
  explicit Progress(std::size_t total) : total_(total), tty_(::isatty(STDERR_FILENO) == 1) {}
  void show(std::size_t done, const std::string& current) {
    if (!tty_)
      return;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(kWidth * done / std::max<std::size_t>(total_, 1));
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '.');
    std::string name = current.size() > 40 ? "..." + current.substr(current.size() - 37) : current;
    std::fprintf(stderr, "\r\033[K[%s] %zu/%zu %s", bar.c_str(), done, total_, name.c_str());
    std::fflush(stderr);
  }
  void clear() {
    if (tty_) {
      std::fprintf(stderr, "\r\033[K");
      std::fflush(stderr);
    }
  }

 private:
  std::size_t total_;
  bool tty_;
};

int runBatch(const ToolOptions& options) {
  const auto start = Clock::now();
  const bool quiet = options.quiet;
  const std::vector<std::string> scenes = listScenes(options.batch);
  const std::vector<std::string> names = outputNames(scenes);
  std::error_code ec;
  fs::create_directories(options.out_dir, ec);
  if (!fs::is_directory(options.out_dir, ec))
    throw OutputError("--out-dir " + options.out_dir + " is not a directory and cannot be made");
  std::vector<std::string> inputs = scenes;
  inputs.push_back(options.model);
  inputs.push_back(options.batch);
  const fs::path dir(options.out_dir);
  auto out = [&](std::size_t i, const char* ext) { return (dir / (names[i] + ext)).string(); };
  pcl_icf_tool::checkOutputPath("--out-dir", (dir / "summary.json").string(), inputs,
                                options.force);
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    pcl_icf_tool::checkOutputPath("--out-dir", out(i, ".json"), inputs, options.force);
    if (options.render_all)
      pcl_icf_tool::checkOutputPath("--render-all", out(i, ".png"), inputs, options.force);
    if (options.output_all)
      pcl_icf_tool::checkOutputPath("--output-all", out(i, ".ply"), inputs, options.force);
  }

  const Model model = loadModel(options.model, options.model_units, quiet);
  json summary_scenes = json::array();
  int found = 0, not_found = 0, errors = 0;
  Progress progress(scenes.size());
  if (!quiet)
    std::printf("%-32s %-10s %7s %7s %8s  %s\n", "scene", "status", "cluster", "score", "time[s]",
                "translation");
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    progress.show(i, scenes[i]);
    Timing timing;
    timing.load_model = model.load_ms;
    timing.build_model = model.build_ms;
    json entry = {{"scene", scenes[i]}, {"json", out(i, ".json")}};
    std::string line;
    try {
      const Scene scene = loadScene(scenes[i], options.units, true);
      timing.load_scene = scene.load_ms;
      const Run run = localize(scene, model, options, true);
      const int code = exitCode(run.loc);
      json result = resultJson(scene, model, options, run, timing);
      writeJson(out(i, ".json"), result, options.force);
      const pcl::PolygonMesh posed = posedModel(scene, model, run);
      if (options.output_all && !posed.polygons.empty()) {
        writePly(out(i, ".ply"), posed, options.force);
        entry["ply"] = out(i, ".ply");
      }
      if (options.render_all) {
        writePng(out(i, ".png"), renderInput(scene, options, posed, caption(scene, model, run)),
                 options.force);
        entry["png"] = out(i, ".png");
      }
      entry["status"] = result["status"];
      entry["exit_code"] = code;
      entry["best"] = result["best"];
      entry["message"] = run.loc.message;
      (code == 0 ? found : code == 1 ? not_found : errors)++;
      std::string translation;
      if (run.loc.best >= 0) {
        const auto& t = result["best"]["translation"];
        translation = fixed(t[0].get<double>(), 4) + " " + fixed(t[1].get<double>(), 4) + " " +
                      fixed(t[2].get<double>(), 4) + " " + pcl_icf_tool::unitsName(scene.units);
      }
      char buf[512];
      std::snprintf(
          buf, sizeof buf, "%-32s %-10s %7s %7s %8.2f  %s",
          fs::path(scenes[i]).filename().string().c_str(), seg::toString(run.loc.status),
          run.loc.best >= 0 ? std::to_string(run.loc.best).c_str() : "-",
          run.loc.best >= 0 ? fixed(result["best"]["score"].get<double>(), 3).c_str() : "-",
          run.ms / 1e3, translation.c_str());
      line = buf;
    } catch (const BadInput& e) {
      ++errors;
      writeJson(out(i, ".json"), errorJson(scenes[i], options.model, e.what()), options.force);
      entry["status"] = "BadInput";
      entry["exit_code"] = 2;
      entry["best"] = nullptr;
      entry["message"] = e.what();
      line = fs::path(scenes[i]).filename().string() + "  error: " + e.what();
    }
    summary_scenes.push_back(entry);
    progress.clear();
    if (!quiet) {
      std::printf("%s\n", line.c_str());
      std::fflush(stdout);
    }
  }
  progress.show(scenes.size(), "done");
  progress.clear();

  const int code = errors > 0 ? 2 : not_found > 0 ? 1 : 0;
  json summary;
  summary["model"] = options.model;
  summary["batch"] = options.batch;
  summary["scenes_total"] = scenes.size();
  summary["found"] = found;
  summary["not_found"] = not_found;
  summary["errors"] = errors;
  summary["exit_code"] = code;
  summary["total_ms"] = msSince(start);
  summary["scenes"] = summary_scenes;
  writeJson((dir / "summary.json").string(), summary, options.force);
  if (!quiet)
    std::printf("\n%zu scenes: %d found, %d not found, %d unreadable; %.1f s; summary in %s\n",
                scenes.size(), found, not_found, errors, msSince(start) / 1e3,
                (dir / "summary.json").string().c_str());
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  ToolOptions options;
  try {
    options = pcl_icf_tool::parseToolOptions(argc, argv);
  } catch (const pcl_icf_tool::UsageError& e) {
    std::fprintf(stderr, "%s: error: %s\n", kProgram, e.what());
    return 2;
  }
  if (options.help) {
    std::printf("%s", pcl_icf_tool::usageText(kProgram).c_str());
    return 0;
  }
  if (!options.verbose) {
    // The tool reports every failure itself, in one line.
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    vtkObject::GlobalWarningDisplayOff();
  }
  try {
    const bool render = !options.render.empty() || options.render_all;
    if (options.view && !pcl_icf_tool::haveDisplay())
      throw OutputError(
          "--view needs a display (DISPLAY is unset or cannot be opened); "
          "use --render FILE.png to get a picture without one");
    // Refuse what we would refuse before spending time on Xvfb or the search.
    if (options.batch.empty())
      checkSingleOutputs(options);
    const std::string display = pcl_icf_tool::ensureDisplayOrReexec(argc, argv, render);
    if (!display.empty())
      throw OutputError(display);
    return options.batch.empty() ? runSingle(options) : runBatch(options);
  } catch (const BadInput& e) {
    std::fprintf(stderr, "%s: error: %s\n", kProgram, e.what());
    return 2;
  } catch (const OutputError& e) {
    std::fprintf(stderr, "%s: error: %s\n", kProgram, e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "%s: error: invalid parameter: %s\n", kProgram, e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: error: out of memory\n", kProgram);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", kProgram, e.what());
    return 2;
  }
}
