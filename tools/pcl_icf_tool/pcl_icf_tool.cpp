/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// pcl_icf_tool: find a CAD mesh's 6D pose in a depth scan (doc/USER_GUIDE.md).
//   pcl_icf_tool SCENE MODEL [options]
//   pcl_icf_tool --batch SCENES MODEL --out-dir DIR [options]
//   pcl_icf_tool --prepare MODEL -o FILE.icfmodel
// Segments the table, localises the model in every cluster, prints the clusters and the best
// pose, and writes on request the result as JSON, the posed model as PLY and a picture.
// Exit codes: 0 object found, 1 nothing accepted, 2 bad usage or bad input.
// One scene: tool_run (inputs, localisation), tool_results (JSON, report, files); many:
// tool_batch.
#include "tool_batch.h"
#include "tool_many.h"
#include "tool_options.h"
#include "tool_output.h"
#include "tool_render.h"
#include "tool_results.h"
#include "tool_run.h"
#include "tool_track.h"

#include <pcl/console/print.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/localization/localizer_fields.h>

#include <vtkObject.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using namespace pcl_icf_tool;

/** Everything a single run would refuse to write, checked before any work. */
void checkSingleOutputs(const ToolOptions& options) {
  std::vector<std::string> inputs = {options.scene, options.model};
  inputs.insert(inputs.end(), options.models.begin(), options.models.end());
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
  const Scene scene = loadScene(options.scene, options.units, quiet, options.depth_png);
  timing.load_scene = scene.load_ms;
  const Model model = loadModel(options.model, options.model_units, quiet, cacheFolder(options));
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
  showPicture(renderInput(scene, options, posed, caption(model, run)), options);
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
  if (options.list_fields) {
    std::printf("%s", pcl::icf::describeFields(pcl::icf::localization::localizerFields()).c_str());
    return 0;
  }
  if (!options.verbose) {
    // The tool reports every failure itself, in one line.
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    vtkObject::GlobalWarningDisplayOff();
  }
  try {
    if (!options.prepare.empty())
      return runPrepare(options);
    const bool render = !options.render.empty() || options.render_all;
    if (options.view && !pcl_icf_tool::haveDisplay())
      throw OutputError(
          "--view needs a display (DISPLAY is unset or cannot be opened); "
          "use --render FILE.png to get a picture without one");
    // Refuse what we would refuse before spending time on Xvfb or the search.
    if (!options.track.empty()) {
      if (!options.render_dir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(options.render_dir, ec);
        if (!std::filesystem::is_directory(options.render_dir))
          throw OutputError("--render-dir " + options.render_dir + ": not a directory" +
                            (ec ? " (" + ec.message() + ")" : std::string()));
      }
      const std::string display =
          pcl_icf_tool::ensureDisplayOrReexec(argc, argv, !options.render_dir.empty());
      if (!display.empty())
        throw OutputError(display);
      return runTrack(options);
    }
    if (options.batch.empty())
      checkSingleOutputs(options);
    const std::string display = pcl_icf_tool::ensureDisplayOrReexec(argc, argv, render);
    if (!display.empty())
      throw OutputError(display);
    if (!options.batch.empty())
      return runBatch(options);
    return options.models.empty() ? runSingle(options) : runMany(options);
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
