/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "tool_track.h"

#include "tool_batch.h"
#include "tool_mesh.h"
#include "tool_output.h"
#include "tool_results.h"
#include "tool_run.h"

#include <pcl/icf/tracking/object_tracker.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <thread>

namespace pcl_icf_tool {

namespace {

namespace trk = pcl::icf::tracking;
namespace fs = std::filesystem;

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
  j["reacquired"] = o.reacquired;
  j["reacquire_ms"] = o.reacquire_ms;
  if (!o.message.empty())
    j["message"] = o.message;
  return j;
}

void printLine(const json& j) {
  std::printf("%s\n", j.dump().c_str());
  std::fflush(stdout);
}

/** The stream: frames in, one JSON line (and a picture) out per frame, the counts for the
 * exit code. The tracker starts on the first good frame. */
class TrackStream {
 public:
  TrackStream(const ToolOptions& options, std::vector<Model> models)
      : options_(options), models_(std::move(models)), tty_(::isatty(STDERR_FILENO) == 1) {
    params_.localizer = options.params;
  }

  /** The picture of frame \a index: RENDER_DIR/NNNN_<stem>.png. */
  std::string picturePath(std::size_t index, const std::string& frame) const {
    char prefix[32];
    std::snprintf(prefix, sizeof(prefix), "%04zu_", index);
    return (fs::path(options_.render_dir) / (prefix + fs::path(frame).stem().string() + ".png"))
        .string();
  }

  /** Tracks the next frame; \a total 0 when unknown (--follow). \throws OutputError when its
   * picture cannot be written. */
  void frame(const std::string& path, std::size_t total) {
    const std::size_t f = frames_++;
    const std::string name = fs::path(path).filename().string();
    json line;
    line["frame"] = f;
    line["file"] = path;
    std::string error;
    std::optional<Scene> scene;
    try {
      scene = loadScene(path, options_.units, true, options_.depth_png);
      if (shape_)
        error = mismatch(*scene, *shape_);
    } catch (const BadInput& e) {
      error = e.what();
    }
    auto skip = [&](const std::string& why) {
      ++bad_;
      line["error"] = why;
      printLine(line);
      if (!options_.quiet)
        std::fprintf(stderr, "%s%s: frame %zu (%s) skipped: %s\n", tty_ ? "\r\033[K" : "", kProgram,
                     f, name.c_str(), why.c_str());
    };
    if (!error.empty())
      return skip(error);
    if (!shape_) {
      shape_ = StreamShape{scene->input->width, scene->input->height, scene->units};
      if (params_.localizer.colour.expected && !scene->info.has_colour)
        params_.localizer.colour.expected.reset();
      tracker_ = std::make_unique<trk::ObjectTracker>(params_);
      for (const auto& m : models_)
        tracker_->addObject(m.icf, fs::path(m.path).stem().string());
    }
    trk::TrackedFrame out;
    try {
      out = tracker_->track(*scene->metres);
    } catch (const std::invalid_argument& e) {  // a frame's VIEWPOINT that is not a rigid motion
      return skip(e.what());
    }
    line["ms"] = out.total_ms;
    json objects = json::array();
    std::string summary;
    for (const auto& o : out.objects) {
      objects.push_back(objectJson(o, scene->metres_per_unit));
      without_pose_ += o.pose ? 0 : 1;
      if (o.refined) {
        refine_ms_.push_back(o.refine_ms);
        verify_ms_.push_back(o.verify_ms);
      }
      summary += " " + o.name + " " + trk::toString(o.state) + " " + fixed(o.confidence, 3);
    }
    line["objects"] = objects;
    if (!options_.render_dir.empty())
      writePicture(f, *scene, out, "frame " + std::to_string(f) + " " + name + ":" + summary);
    printLine(line);
    if (options_.quiet)
      return;
    const std::string count =
        total ? std::to_string(f + 1) + "/" + std::to_string(total) : std::to_string(f + 1);
    std::fprintf(stderr, tty_ ? "\r\033[K[%s] %s:%s (%.0f ms)" : "[%s] %s:%s (%.0f ms)\n",
                 count.c_str(), name.c_str(), summary.c_str(), out.total_ms);
  }

  /** The summary on stderr and the exit code as --batch's: 2 when a frame could not be used
   * (or none came), else 1 when an object had no pose in some frame, else 0. */
  int finish() const {
    if (!options_.quiet) {
      auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v.empty() ? 0.0 : v[v.size() / 2];
      };
      std::fprintf(stderr,
                   "%s%zu frames, %d skipped; per object and frame, median refinement %.1f ms, "
                   "verification %.1f ms\n",
                   tty_ ? "\r\033[K" : "", frames_, bad_, median(refine_ms_), median(verify_ms_));
    }
    if (bad_ > 0 || frames_ == 0)
      return 2;
    return without_pose_ > 0 ? 1 : 0;
  }

  std::size_t frames() const { return frames_; }

 private:
  /** The frame with every pose drawn, each object in its colour (the first in the tool's
   * model colour), a legend line per object when there are several. */
  void writePicture(std::size_t f, const Scene& scene, const trk::TrackedFrame& out,
                    const std::string& text) const {
    RenderInput in = renderInput(scene, options_, {}, text);
    const std::vector<std::string> names = modelNames(options_.models);
    for (std::size_t k = 0; k < out.objects.size(); ++k) {
      const Eigen::Vector3f colour = k == 0 ? options_.render_colour : objectColour(k);
      if (models_.size() > 1)
        in.legend.push_back({names[k] + (out.objects[k].pose ? "" : ": not found"), colour});
      if (!out.objects[k].pose)
        continue;
      Eigen::Matrix4d pose = out.objects[k].pose->matrix().cast<double>();
      pose.topRightCorner<3, 1>() /= scene.metres_per_unit;
      in.models.push_back(
          {posedMesh(models_[k].mesh, pose, models_[k].metres_per_unit / scene.metres_per_unit),
           colour});
    }
    writePng(picturePath(f, scene.path), in, options_.force);
  }

  const ToolOptions& options_;
  std::vector<Model> models_;
  bool tty_;
  trk::TrackerParams params_;
  std::unique_ptr<trk::ObjectTracker> tracker_;
  std::optional<StreamShape> shape_;
  std::size_t frames_ = 0;
  int bad_ = 0, without_pose_ = 0;
  std::vector<double> refine_ms_, verify_ms_;
};

/** The frames of a folder as they become complete: a scene file (listScenes' extensions; not
 * a hidden ".name") is taken once its size and modification time have stayed the same for
 * kSettle (a frame renamed into the folder: after kSettle), each once, the ready ones in name
 * order. */
class FolderWatch {
 public:
  static constexpr std::chrono::milliseconds kSettle{300};

  explicit FolderWatch(fs::path dir) : dir_(std::move(dir)) {}

  /** The frames complete since the last call, in name order; \a changed is set when a file
   * is still being written. */
  std::vector<std::string> ready(bool& changed) {
    changed = false;
    const auto now = Clock::now();
    std::vector<std::string> out;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir_, ec)) {
      const std::string path = entry.path().string();
      const bool hidden = entry.path().filename().string().rfind('.', 0) == 0;
      if (hidden || !entry.is_regular_file(ec) || !isSceneFile(path) || taken_.count(path))
        continue;
      const auto size = entry.file_size(ec);
      const auto time = entry.last_write_time(ec);
      if (ec)
        continue;
      auto it = pending_.find(path);
      if (it == pending_.end() || it->second.size != size || it->second.time != time) {
        pending_[path] = {size, time, now};
        changed = true;
      } else if (now - it->second.since >= kSettle) {
        out.push_back(path);
      }
    }
    std::sort(out.begin(), out.end());
    for (const auto& p : out) {
      pending_.erase(p);
      taken_.insert(p);
    }
    return out;
  }

 private:
  struct Seen {
    std::uintmax_t size;
    fs::file_time_type time;
    Clock::time_point since;
  };
  fs::path dir_;
  std::map<std::string, Seen> pending_;
  std::set<std::string> taken_;
};

}  // namespace

int runTrack(const ToolOptions& options) {
  std::vector<std::string> frames;
  if (options.follow) {
    if (!fs::is_directory(options.track))
      throw BadInput(options.track + ": --follow watches a directory");
  } else {
    frames = listScenes(options.track, "--track");
  }
  std::vector<Model> models;
  for (const auto& path : options.models)
    models.push_back(loadModel(path, options.model_units, options.quiet, cacheFolder(options)));
  TrackStream stream(options, std::move(models));
  if (!options.follow) {
    if (!options.render_dir.empty())
      for (std::size_t f = 0; f < frames.size(); ++f)
        checkOutputPath("--render-dir", stream.picturePath(f, frames[f]), frames, options.force);
    for (const auto& frame : frames)
      stream.frame(frame, frames.size());
    return stream.finish();
  }
  // --follow: until no frame appeared (and none was being written) for --idle-seconds.
  FolderWatch watch(options.track);
  const auto idle = std::chrono::duration<double>(options.idle_seconds);
  auto last = Clock::now();
  for (;;) {
    bool changed = false;
    for (const auto& frame : watch.ready(changed)) {
      stream.frame(frame, 0);
      changed = true;
    }
    if (changed)
      last = Clock::now();
    else if (Clock::now() - last >= idle)
      break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  if (stream.frames() == 0 && !options.quiet)
    std::fprintf(stderr, "%s: error: no frame appeared in %s within %g s\n", kProgram,
                 options.track.c_str(), options.idle_seconds);
  return stream.finish();
}

}  // namespace pcl_icf_tool
