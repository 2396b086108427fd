/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "tool_batch.h"

#include "tool_output.h"
#include "tool_results.h"
#include "tool_run.h"

#include <pcl/icf/io/mesh_io.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

namespace pcl_icf_tool {

namespace fs = std::filesystem;
namespace localization = pcl::icf::localization;

bool isSceneFile(const std::string& path) {
  const std::string ext = pcl::icf::io::fileExtension(path);
  return ext == "pcd" || ext == "ply" || ext == "xyz" || ext == "asc";
}

std::vector<std::string> listScenes(const std::string& source, const std::string& option) {
  std::vector<std::string> scenes;
  std::error_code ec;
  if (fs::is_directory(source, ec)) {
    for (const auto& entry : fs::directory_iterator(source, ec))
      if (entry.is_regular_file(ec) && isSceneFile(entry.path().string()))
        scenes.push_back(entry.path().string());
    std::sort(scenes.begin(), scenes.end());
    if (scenes.empty())
      throw BadInput(source + ": no .pcd, .ply, .xyz or .asc file in this directory");
    return scenes;
  }
  try {
    pcl::icf::io::requireReadableFile(source);
  } catch (const pcl::icf::io::FileError& e) {
    throw BadInput(std::string(e.what()) + " (" + option + " takes a directory or a list file)");
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

namespace {

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

/** Where a batch writes: --out-dir made if needed, one base name per scene. */
struct BatchOutputs {
  fs::path dir;
  std::vector<std::string> names;
  std::string path(std::size_t i, const char* ext) const {
    return (dir / (names[i] + ext)).string();
  }
  std::string summary() const { return (dir / "summary.json").string(); }
};

/** Makes --out-dir and checks every file the batch would write, before any work. */
BatchOutputs prepareOutputs(const ToolOptions& options, const std::vector<std::string>& scenes) {
  BatchOutputs out{fs::path(options.out_dir), outputNames(scenes)};
  std::error_code ec;
  fs::create_directories(out.dir, ec);
  if (!fs::is_directory(out.dir, ec))
    throw OutputError("--out-dir " + options.out_dir + " is not a directory and cannot be made");
  std::vector<std::string> inputs = scenes;
  inputs.push_back(options.model);
  inputs.push_back(options.batch);
  checkOutputPath("--out-dir", out.summary(), inputs, options.force);
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    checkOutputPath("--out-dir", out.path(i, ".json"), inputs, options.force);
    if (options.render_all)
      checkOutputPath("--render-all", out.path(i, ".png"), inputs, options.force);
    if (options.output_all)
      checkOutputPath("--output-all", out.path(i, ".ply"), inputs, options.force);
  }
  return out;
}

/** One scene of the batch: its summary entry, exit code and table line. */
struct SceneOutcome {
  json entry;
  int code = 2;
  std::string line;
};

/** Localizes the model in scene \a i and writes its JSON (and PLY, PNG on request); an
 * unreadable scene gives an error JSON and code 2, never an exception. */
SceneOutcome runScene(std::size_t i, const std::string& scene_path, const Model& model,
                      const ToolOptions& options, const BatchOutputs& out) {
  SceneOutcome o;
  o.entry = {{"scene", scene_path}, {"json", out.path(i, ".json")}};
  Timing timing;
  timing.load_model = model.load_ms;
  timing.build_model = model.build_ms;
  try {
    const Scene scene = loadScene(scene_path, options.units, true, options.depth_png);
    timing.load_scene = scene.load_ms;
    const Run run = localize(scene, model, options, true);
    o.code = exitCode(run.loc);
    json result = resultJson(scene, model, options, run, timing);
    writeJson(out.path(i, ".json"), result, options.force);
    const pcl::PolygonMesh posed = posedModel(scene, model, run);
    if (options.output_all && !posed.polygons.empty()) {
      writePly(out.path(i, ".ply"), posed, options.force);
      o.entry["ply"] = out.path(i, ".ply");
    }
    if (options.render_all) {
      writePng(out.path(i, ".png"), renderInput(scene, options, posed, caption(model, run)),
               options.force);
      o.entry["png"] = out.path(i, ".png");
    }
    o.entry["status"] = result["status"];
    o.entry["exit_code"] = o.code;
    o.entry["best"] = result["best"];
    o.entry["message"] = run.loc.message;
    std::string translation;
    if (run.loc.best >= 0) {
      const auto& t = result["best"]["translation"];
      translation = fixed(t[0].get<double>(), 4) + " " + fixed(t[1].get<double>(), 4) + " " +
                    fixed(t[2].get<double>(), 4) + " " + unitsName(scene.units);
    }
    char buf[512];
    std::snprintf(buf, sizeof buf, "%-32s %-10s %7s %7s %8.2f  %s",
                  fs::path(scene_path).filename().string().c_str(),
                  localization::toString(run.loc.status).c_str(),
                  run.loc.best >= 0 ? std::to_string(run.loc.best).c_str() : "-",
                  run.loc.best >= 0 ? fixed(result["best"]["score"].get<double>(), 3).c_str() : "-",
                  run.ms / 1e3, translation.c_str());
    o.line = buf;
  } catch (const BadInput& e) {
    o.code = 2;
    writeJson(out.path(i, ".json"), errorJson(scene_path, options.model, e.what()), options.force);
    o.entry["status"] = "BadInput";
    o.entry["exit_code"] = 2;
    o.entry["best"] = nullptr;
    o.entry["message"] = e.what();
    o.line = fs::path(scene_path).filename().string() + "  error: " + e.what();
  }
  return o;
}

}  // namespace

int runBatch(const ToolOptions& options) {
  const auto start = Clock::now();
  const bool quiet = options.quiet;
  const std::vector<std::string> scenes = listScenes(options.batch, "--batch");
  const BatchOutputs out = prepareOutputs(options, scenes);
  const Model model = loadModel(options.model, options.model_units, quiet, cacheFolder(options));

  json summary_scenes = json::array();
  int counts[3] = {0, 0, 0};  // found, not found, unreadable: by exit code
  Progress progress(scenes.size());
  if (!quiet)
    std::printf("%-32s %-10s %7s %7s %8s  %s\n", "scene", "status", "cluster", "score", "time[s]",
                "translation");
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    progress.show(i, scenes[i]);
    const SceneOutcome o = runScene(i, scenes[i], model, options, out);
    ++counts[o.code];
    summary_scenes.push_back(o.entry);
    progress.clear();
    if (!quiet) {
      std::printf("%s\n", o.line.c_str());
      std::fflush(stdout);
    }
  }
  progress.show(scenes.size(), "done");
  progress.clear();

  const int code = counts[2] > 0 ? 2 : counts[1] > 0 ? 1 : 0;
  json summary;
  summary["model"] = options.model;
  summary["batch"] = options.batch;
  summary["scenes_total"] = scenes.size();
  summary["found"] = counts[0];
  summary["not_found"] = counts[1];
  summary["errors"] = counts[2];
  summary["exit_code"] = code;
  summary["total_ms"] = msSince(start);
  summary["scenes"] = summary_scenes;
  writeJson(out.summary(), summary, options.force);
  if (!quiet)
    std::printf("\n%zu scenes: %d found, %d not found, %d unreadable; %.1f s; summary in %s\n",
                scenes.size(), counts[0], counts[1], counts[2], msSince(start) / 1e3,
                out.summary().c_str());
  return code;
}

}  // namespace pcl_icf_tool
