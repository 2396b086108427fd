/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "tool_results.h"

#include "tool_output.h"

#include <pcl/io/ply_io.h>

#include <cstdio>
#include <fstream>

namespace pcl_icf_tool {

namespace localization = pcl::icf::localization;
namespace seg = pcl::icf::segmentation;

namespace {

/** A 4x4 pose as rows. */
json poseRows(const Eigen::Matrix4d& pose) {
  json rows = json::array();
  for (int r = 0; r < 4; ++r)
    rows.push_back({pose(r, 0), pose(r, 1), pose(r, 2), pose(r, 3)});
  return rows;
}

/** Model -> scene in the scene's units. */
Eigen::Matrix4d inSceneUnits(const Eigen::Isometry3f& pose, double metres_per_unit) {
  Eigen::Matrix4d m = pose.matrix().cast<double>();
  m.block<3, 1>(0, 3) /= metres_per_unit;
  return m;
}

json alternativesJson(const localization::ClusterLocalization& c, const Scene& scene) {
  json list = json::array();
  for (const auto& alt : c.alternatives)
    list.push_back({{"pose", poseRows(inSceneUnits(alt.object_pose, scene.metres_per_unit))},
                    {"confidence", alt.verification.confidence},
                    {"residual", alt.verification.residual},
                    {"turn_axis_model", {alt.axis.x(), alt.axis.y(), alt.axis.z()}},
                    {"turn_deg", alt.turn_deg},
                    {"origin_offset", alt.translation_offset / scene.metres_per_unit}});
  return list;
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

}  // namespace

json clusterJson(const localization::ClusterLocalization& c, int index, const Scene& scene) {
  const Eigen::Matrix4d pose = scenePose(c, scene.metres_per_unit);
  const Eigen::Quaterniond q = quaternionOf(pose);
  const json rows = poseRows(pose);
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
  j["confidence"] = c.verification.confidence;
  j["ambiguous"] = !c.alternatives.empty();
  j["alternatives"] = alternativesJson(c, scene);
  j["turned"] = c.turned;
  j["verification"] = {{"judged_pixels", c.verification.model_pixels},
                       {"supported", c.verification.supported},
                       {"seen_through", c.verification.seen_through},
                       {"occluded", c.verification.occluded},
                       {"below_support", c.verification.below_support},
                       {"isolated_conflicts", c.verification.isolated_conflicts},
                       {"missing", c.verification.missing},
                       {"out_of_view", c.verification.out_of_view},
                       {"on_background", c.verification.on_background},
                       {"visible_support", c.verification.visible_support},
                       {"residual", c.verification.residual},
                       {"silhouette_continuation", c.verification.silhouette_continuation},
                       {"silhouette_pixels", c.verification.silhouette_pixels},
                       {"occluder_continuation", c.verification.occluder_continuation},
                       {"occluded_by_support", c.verification.occluded_by_support},
                       {"local_misfit", c.verification.local_misfit},
                       {"silhouette_offset", c.verification.silhouette_offset},
                       {"silhouette_edges", c.verification.silhouette_edges},
                       {"allowed_offset", c.verification.allowed_offset},
                       {"sunk_into_support", c.verification.sunk_into_support},
                       {"support_tolerance", c.verification.support_tolerance}};
  j["colour_similarity"] = c.colour_similarity ? json(*c.colour_similarity) : json(nullptr);
  j["time_ms"] = c.icf.time_ms;
  return j;
}

json resultJson(const Scene& scene, const Model& model, const ToolOptions& options, const Run& run,
                const Timing& timing) {
  json j;
  j["scene"] = scene.path;
  j["model"] = model.path;
  j["units"] = pcl_icf_tool::unitsName(scene.units);
  j["model_units"] = pcl_icf_tool::unitsName(model.units);
  j["seed"] = options.params.seed;
  j["strategy"] = pcl::icf::toString(options.params.strategy);
  j["fallback"] = pcl::icf::toString(options.params.fallback);
  j["segment"] = options.params.segment;
  {
    const Eigen::Isometry3d camera = run.loc.camera_pose.cast<double>();
    const Eigen::Quaterniond q = quaternionOf(camera.matrix());
    const Eigen::Vector3d position = camera.translation() / scene.metres_per_unit;
    j["camera"] = {{"position", {position.x(), position.y(), position.z()}},
                   {"quaternion_wxyz", {q.w(), q.x(), q.y(), q.z()}}};
  }
  j["status"] = localization::toString(run.loc.status);
  j["message"] = run.loc.message;
  j["exit_code"] = exitCode(run.loc);
  j["best"] = nullptr;
  json clusters = json::array();
  for (std::size_t k = 0; k < run.loc.clusters.size(); ++k)
    clusters.push_back(clusterJson(run.loc.clusters[k], static_cast<int>(k), scene));
  if (run.loc.best >= 0)
    j["best"] = clusters[static_cast<std::size_t>(run.loc.best)];
  json instances = json::array();
  for (int k : run.loc.instances)
    instances.push_back(clusters[static_cast<std::size_t>(k)]);
  j["instances"] = instances;
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
      {"radius", model.icf->radius() / scene.metres_per_unit},
      {"from_cache", model.from_cache},
      {"from_prepared_file", model.from_prepared_file}};
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
  j["instances"] = json::array();
  j["clusters"] = json::array();
  return j;
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
                seg::toString(loc.segmentation.status).c_str(),
                loc.segmentation.plane.inliers.size(), loc.segmentation.clusters.size(),
                loc.clusters.size());
  if (!loc.clusters.empty()) {
    std::printf("\n  #  points   confidence  coverage  inliers  rmse[mm]  result\n");
    for (std::size_t k = 0; k < loc.clusters.size(); ++k) {
      const auto& c = loc.clusters[k];
      std::printf("%3zu %7zu  %11.3f %9.3f %8.3f %9.2f  %s%s\n", k, c.indices.indices.size(),
                  c.verification.confidence, c.icf.quality.surface_coverage,
                  c.icf.quality.inlier_ratio, 1e3 * c.icf.quality.rmse,
                  static_cast<int>(k) == loc.best ? "BEST, " : "",
                  c.accepted ? "accepted" : ("rejected: " + c.reason).c_str());
    }
  }
  std::printf("\n");
  if (loc.best < 0) {
    std::printf("no object found: %s (%s)\n", localization::toString(loc.status).c_str(),
                loc.message.c_str());
    if (segment && loc.status == localization::LocalizationStatus::NoClusters)
      std::printf("       (for a cloud that holds one object, use --no-segment)\n");
  } else {
    const auto& c = loc.clusters[static_cast<std::size_t>(loc.best)];
    const Eigen::Matrix4d pose = scenePose(c, scene.metres_per_unit);
    const Eigen::Quaterniond q = quaternionOf(pose);
    std::printf("best   cluster %d by %s, confidence %.3f, score %.3f\n", loc.best,
                c.icf.method.c_str(), c.verification.confidence, c.score);
    std::printf("pose   model -> scene, %s:\n", units);
    for (int r = 0; r < 4; ++r)
      std::printf("       %10.6f %10.6f %10.6f %12.6f\n", pose(r, 0), pose(r, 1), pose(r, 2),
                  pose(r, 3));
    std::printf("quaternion wxyz  %.6f %.6f %.6f %.6f\n", q.w(), q.x(), q.y(), q.z());
    std::printf("translation      %.6f %.6f %.6f %s\n", pose(0, 3), pose(1, 3), pose(2, 3), units);
    for (const auto& alt : c.alternatives)
      std::printf(
          "ambiguous: turned %.0f deg about (%.2f, %.2f, %.2f) in the model's frame, the "
          "origin %s %s away, explains the depth as well (confidence %.3f)\n",
          alt.turn_deg, alt.axis.x(), alt.axis.y(), alt.axis.z(),
          fixed(alt.translation_offset / scene.metres_per_unit, 4).c_str(), units,
          alt.verification.confidence);
    for (std::size_t n = 1; n < loc.instances.size(); ++n) {
      const auto& other = loc.clusters[static_cast<std::size_t>(loc.instances[n])];
      const Eigen::Matrix4d p = scenePose(other, scene.metres_per_unit);
      std::printf("instance %zu  cluster %d, confidence %.3f, at %.6f %.6f %.6f %s\n", n + 1,
                  loc.instances[n], other.verification.confidence, p(0, 3), p(1, 3), p(2, 3),
                  units);
    }
  }
  std::printf("time   %.0f ms (segmentation %.0f, registration %.0f)\n", run.ms,
              loc.segmentation_ms, loc.registration_ms);
}

void writePly(const std::string& path, const pcl::PolygonMesh& mesh, bool force) {
  pcl_icf_tool::writeAtomically(path, force, [&](const std::string& tmp) {
    if (pcl::io::savePLYFileBinary(tmp, mesh) < 0)
      throw std::runtime_error("PCL's PLY writer failed");
  });
}

void writePng(const std::string& path, const RenderInput& input, bool force) {
  pcl_icf_tool::writeAtomically(
      path, force, [&](const std::string& tmp) { pcl_icf_tool::renderPng(input, tmp); });
}

void showPicture(const RenderInput& input, const ToolOptions& options) {
  if (!options.render.empty()) {
    writePng(options.render, input, options.force);
    if (!options.quiet)
      std::printf("wrote  %s\n", options.render.c_str());
  }
  std::fflush(stdout);
  if (options.view)
    runViewer(input);
}

}  // namespace pcl_icf_tool
