/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "tool_many.h"

#include "tool_mesh.h"
#include "tool_render.h"

#include "tool_results.h"
#include "tool_run.h"

#include <pcl/icf/localization/objects_localizer.h>

#include <cstdio>
#include <filesystem>

namespace pcl_icf_tool {

namespace localization = pcl::icf::localization;

namespace {

json frameJson(const Scene& scene, const std::vector<Model>& models,
               const std::vector<std::string>& names, const ToolOptions& options,
               const localization::ObjectsLocalization& all, double load_scene_ms,
               double localization_ms, Clock::time_point start) {
  json j;
  j["scene"] = scene.path;
  j["units"] = pcl_icf_tool::unitsName(scene.units);
  j["seed"] = options.params.seed;
  j["segment"] = options.params.segment;
  j["status"] = localization::toString(all.status);
  j["message"] = all.message;
  j["exit_code"] = all.status == localization::LocalizationStatus::Found ? 0 : 1;
  json objects = json::array();
  std::vector<json> clusters_of(models.size());
  for (std::size_t k = 0; k < models.size(); ++k) {
    const localization::Localization& loc = all.objects[k];
    json& clusters = clusters_of[k] = json::array();
    for (std::size_t h = 0; h < loc.clusters.size(); ++h)
      clusters.push_back(clusterJson(loc.clusters[h], static_cast<int>(h), scene));
    json instances = json::array();
    for (const int h : loc.instances)
      instances.push_back(clusters[static_cast<std::size_t>(h)]);
    objects.push_back({{"model", models[k].path},
                       {"name", names[k]},
                       {"model_units", pcl_icf_tool::unitsName(models[k].units)},
                       {"max_instances", options.model_counts[k]},
                       {"from_cache", models[k].from_cache},
                       {"from_prepared_file", models[k].from_prepared_file},
                       {"status", localization::toString(loc.status)},
                       {"message", loc.message},
                       {"instances", instances},
                       {"clusters", clusters},
                       {"timing_ms",
                        {{"load_model", models[k].load_ms},
                         {"build_model", models[k].build_ms},
                         {"hypotheses", loc.hypotheses_ms},
                         {"ranking", loc.ranking_ms},
                         {"judging", loc.judging_ms}}}});
  }
  j["objects"] = objects;
  json instances = json::array();
  for (const auto& i : all.instances) {
    const json& c =
        clusters_of[static_cast<std::size_t>(i.object)][static_cast<std::size_t>(i.hypothesis)];
    instances.push_back({{"object", i.object},
                         {"name", names[static_cast<std::size_t>(i.object)]},
                         {"cluster", i.hypothesis},
                         {"confidence", c["confidence"]},
                         {"pose", c["pose"]}});
  }
  j["instances"] = instances;
  j["timing_ms"] = {{"load_scene", load_scene_ms},
                    {"scene", all.scene_ms},
                    {"selection", all.selection_ms},
                    {"localization", localization_ms},
                    {"total", msSince(start)}};
  return j;
}

void printFrame(const Scene& scene, const std::vector<std::string>& names,
                const localization::ObjectsLocalization& all, double ms) {
  const char* units = pcl_icf_tool::unitsName(scene.units);
  std::printf("scene  %s: %u x %u, %zu finite points, %s\n", scene.path.c_str(), scene.input->width,
              scene.input->height, scene.info.finite_points, units);
  std::printf("\n  object                          instances  confidence  result\n");
  for (std::size_t k = 0; k < names.size(); ++k) {
    const localization::Localization& loc = all.objects[k];
    if (loc.instances.empty()) {
      std::printf("  %-32s %9d  %10s  not found: %s\n", names[k].c_str(), 0, "-",
                  loc.message.c_str());
      continue;
    }
    for (std::size_t n = 0; n < loc.instances.size(); ++n) {
      const auto& c = loc.clusters[static_cast<std::size_t>(loc.instances[n])];
      const Eigen::Matrix4d pose = scenePose(c, scene.metres_per_unit);
      std::printf("  %-32s %9zu  %10.3f  at %.4f %.4f %.4f %s\n", n == 0 ? names[k].c_str() : "",
                  n + 1, c.verification.confidence, pose(0, 3), pose(1, 3), pose(2, 3), units);
    }
  }
  std::printf("\ntime   %.0f ms (scene %.0f, selection %.0f)\n", ms, all.scene_ms,
              all.selection_ms);
}

/** The frame's picture: every accepted instance in its object's colour (the first object's is
 * --render-color), a legend line per object. */
RenderInput framePicture(const Scene& scene, const std::vector<Model>& models,
                         const std::vector<std::string>& names, const ToolOptions& options,
                         const localization::ObjectsLocalization& all) {
  RenderInput in = renderInput(scene, options, {}, "");
  std::size_t found = 0;
  for (std::size_t k = 0; k < models.size(); ++k) {
    const localization::Localization& loc = all.objects[k];
    const Eigen::Vector3f colour = k == 0 ? options.render_colour : objectColour(k);
    std::string line = names[k] + ": ";
    if (loc.instances.empty())
      line += "not found";
    for (std::size_t n = 0; n < loc.instances.size(); ++n) {
      const auto& c = loc.clusters[static_cast<std::size_t>(loc.instances[n])];
      in.models.push_back({posedMesh(models[k].mesh, scenePose(c, scene.metres_per_unit),
                                     models[k].metres_per_unit / scene.metres_per_unit),
                           colour});
      line += (n == 0 ? "confidence " : ", ") + fixed(c.verification.confidence, 2);
    }
    found += !loc.instances.empty();
    in.legend.push_back({line, colour});
  }
  in.caption = std::filesystem::path(scene.path).filename().string() + ": " +
               std::to_string(found) + " of " + std::to_string(models.size()) + " objects found";
  return in;
}

}  // namespace

int runMany(const ToolOptions& options) {
  const auto start = Clock::now();
  const bool quiet = options.quiet;
  const Scene scene = loadScene(options.scene, options.units, quiet, options.depth_png);
  std::vector<Model> models;
  for (const auto& path : options.models)
    models.push_back(loadModel(path, options.model_units, quiet, cacheFolder(options)));
  const std::vector<std::string> names = modelNames(options.models);
  std::vector<localization::ObjectQuery> queries;
  for (std::size_t k = 0; k < models.size(); ++k)
    queries.push_back({models[k].icf, names[k], options.model_counts[k]});

  const auto began = Clock::now();
  const localization::ObjectsLocalization all =
      localization::localizeObjects(*scene.metres, queries, localizerParams(scene, options, quiet));
  const double ms = msSince(began);
  if (all.status == localization::LocalizationStatus::BadScene)
    throw BadInput(options.scene + ": " + all.message +
                   (options.params.segment ? " (for a cloud that holds one object, use "
                                             "--no-segment)"
                                           : ""));
  if (!quiet)
    printFrame(scene, names, all, ms);
  if (!options.json.empty()) {
    writeJson(options.json, frameJson(scene, models, names, options, all, scene.load_ms, ms, start),
              options.force);
    if (!quiet)
      std::printf("wrote  %s\n", options.json.c_str());
  }
  if (!options.render.empty() || options.view)
    showPicture(framePicture(scene, models, names, options, all), options);
  return all.status == localization::LocalizationStatus::Found ? 0 : 1;
}

}  // namespace pcl_icf_tool
