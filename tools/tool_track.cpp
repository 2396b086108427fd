/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "tool_track.h"

#include "tool_batch.h"
#include "tool_results.h"
#include "tool_run.h"

#include <pcl/icf/tracking/object_tracker.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>

namespace pcl_icf_tool {

namespace {

namespace trk = pcl::icf::tracking;

/** What every frame of the stream must share with the first good one. */
struct StreamShape {
  std::uint32_t width = 0, height = 0;
  Units units = Units::Metres;
};

/** Why \a scene cannot join a stream of \a shape ("" when it can). */
std::string mismatch(const Scene& scene, const StreamShape& shape) {
  if (scene.input->width != shape.width || scene.input->height != shape.height)
    return "its size is " + std::to_string(scene.input->width) + "x" +
           std::to_string(scene.input->height) + ", the stream's frames are " +
           std::to_string(shape.width) + "x" + std::to_string(shape.height);
  if (scene.units != shape.units)
    return std::string("it is in ") + unitsName(scene.units) + ", the stream in " +
           unitsName(shape.units);
  return {};
}

json objectJson(const trk::ObjectTrack& o, double metres_per_unit) {
  json j;
  j["name"] = o.name;
  j["state"] = trk::toString(o.state);
  j["confidence"] = o.confidence;
  if (o.pose) {
    Eigen::Matrix4d pose = o.pose->matrix().cast<double>();
    pose.topRightCorner<3, 1>() /= metres_per_unit;
    const Eigen::Quaterniond q = quaternionOf(pose);
    json rows = json::array();
    for (int r = 0; r < 4; ++r)
      rows.push_back({pose(r, 0), pose(r, 1), pose(r, 2), pose(r, 3)});
    j["pose"] = rows;
    j["quaternion_wxyz"] = {q.w(), q.x(), q.y(), q.z()};
    j["translation"] = {pose(0, 3), pose(1, 3), pose(2, 3)};
  } else {
    j["pose"] = nullptr;
  }
  j["searched"] = o.searched;
  j["refine_ms"] = o.refine_ms;
  j["verify_ms"] = o.verify_ms;
  j["search_ms"] = o.search_ms;
  if (!o.message.empty())
    j["message"] = o.message;
  return j;
}

void printLine(const json& j) {
  std::printf("%s\n", j.dump().c_str());
  std::fflush(stdout);
}

}  // namespace

int runTrack(const ToolOptions& options) {
  const bool quiet = options.quiet;
  const std::vector<std::string> frames = listScenes(options.track, "--track");
  std::vector<Model> models;
  for (const auto& path : options.models)
    models.push_back(loadModel(path, options.model_units, quiet));

  trk::TrackerParams params;
  params.localizer = options.params;
  std::unique_ptr<trk::ObjectTracker> tracker;
  std::optional<StreamShape> shape;
  const bool tty = ::isatty(STDERR_FILENO) == 1;
  int bad = 0, without_pose = 0;
  std::vector<double> refine_ms, verify_ms;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const std::string name = std::filesystem::path(frames[f]).filename().string();
    json line;
    line["frame"] = f;
    line["file"] = frames[f];
    std::string error;
    std::optional<Scene> scene;
    try {
      scene = loadScene(frames[f], options.units, true);
      if (shape)
        error = mismatch(*scene, *shape);
    } catch (const BadInput& e) {
      error = e.what();
    }
    auto skip = [&](const std::string& why) {
      ++bad;
      line["error"] = why;
      printLine(line);
      if (!quiet)
        std::fprintf(stderr, "%s: frame %zu (%s) skipped: %s\n", kProgram, f, name.c_str(),
                     why.c_str());
    };
    if (!error.empty()) {
      skip(error);
      continue;
    }
    if (!shape) {
      shape = StreamShape{scene->input->width, scene->input->height, scene->units};
      if (params.localizer.colour.expected && !scene->info.has_colour)
        params.localizer.colour.expected.reset();
      tracker = std::make_unique<trk::ObjectTracker>(params);
      for (const auto& m : models)
        tracker->addObject(m.icf, std::filesystem::path(m.path).stem().string());
    }
    trk::TrackedFrame out;
    try {
      out = tracker->track(*scene->metres);
    } catch (const std::invalid_argument& e) {  // a frame's VIEWPOINT that is not a rigid motion
      skip(e.what());
      continue;
    }
    line["ms"] = out.total_ms;
    json objects = json::array();
    std::string summary;
    for (const auto& o : out.objects) {
      objects.push_back(objectJson(o, scene->metres_per_unit));
      without_pose += o.pose ? 0 : 1;
      if (o.refined) {
        refine_ms.push_back(o.refine_ms);
        verify_ms.push_back(o.verify_ms);
      }
      summary += " " + o.name + " " + trk::toString(o.state) + " " + fixed(o.confidence, 3);
    }
    line["objects"] = objects;
    printLine(line);
    if (!quiet)
      std::fprintf(stderr,
                   tty ? "\r\033[K[%zu/%zu] %s:%s (%.0f ms)" : "[%zu/%zu] %s:%s (%.0f ms)\n", f + 1,
                   frames.size(), name.c_str(), summary.c_str(), out.total_ms);
  }
  if (!quiet) {
    auto median = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v.empty() ? 0.0 : v[v.size() / 2];
    };
    std::fprintf(stderr,
                 "%s%zu frames, %d skipped; per object and frame, median refinement %.1f ms, "
                 "verification %.1f ms\n",
                 tty ? "\r\033[K" : "", frames.size(), bad, median(refine_ms), median(verify_ms));
  }
  if (bad > 0)
    return 2;
  return without_pose > 0 ? 1 : 0;
}

}  // namespace pcl_icf_tool
