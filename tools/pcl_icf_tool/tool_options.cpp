/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "tool_options.h"

#include <pcl/icf/localization/localizer_fields.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

namespace pcl_icf_tool {

const char* unitsName(Units units) {
  switch (units) {
    case Units::Metres:
      return "m";
    case Units::Millimetres:
      return "mm";
    default:
      return "auto";
  }
}

double metresPerUnit(Units units) {
  return units == Units::Millimetres ? 1e-3 : 1.0;
}

namespace {

using pcl_icf_tools::ArgumentReader;
using pcl_icf_tools::isOption;
using pcl_icf_tools::parseFraction;
using pcl_icf_tools::parseInteger;
using pcl_icf_tools::parseNumber;
using pcl_icf_tools::parsePositive;
using pcl_icf_tools::parseSeed;

Units parseUnits(const std::string& option, const std::string& text) {
  if (text == "m")
    return Units::Metres;
  if (text == "mm")
    return Units::Millimetres;
  if (text == "auto")
    return Units::Auto;
  throw UsageError(option + ": '" + text + "' is not m, mm or auto");
}

/** "R,G,B" with integers in [0, 255], or "#rrggbb"; channels returned in [0, 1]. */
Eigen::Vector3f parseColour(const std::string& option, const std::string& text) {
  Eigen::Vector3f c;
  if (text.size() == 7 && text[0] == '#') {
    for (int i = 0; i < 3; ++i) {
      unsigned v = 0;
      const char* b = text.data() + 1 + 2 * i;
      const auto [ptr, ec] = std::from_chars(b, b + 2, v, 16);
      if (ec != std::errc() || ptr != b + 2)
        throw UsageError(option + ": '" + text + "' is not a colour (R,G,B or #rrggbb)");
      c[i] = static_cast<float>(v) / 255.f;
    }
    return c;
  }
  std::stringstream in(text);
  std::string part;
  int i = 0;
  while (std::getline(in, part, ',')) {
    if (i == 3)
      throw UsageError(option + ": '" + text + "' has more than 3 channels (R,G,B)");
    c[i++] = static_cast<float>(parseInteger(option, part, 0, 255)) / 255.f;
  }
  if (i != 3)
    throw UsageError(option + ": '" + text + "' is not a colour (R,G,B in 0-255, or #rrggbb)");
  return c;
}

/** Comma-separated numbers. */
std::vector<double> parseNumbers(const std::string& option, const std::string& text) {
  std::vector<double> v;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ','))
    v.push_back(parseNumber(option, part));
  return v;
}

/** "X,Y,Z" or "X,Y,Z,QW,QX,QY,QZ": the camera's position (scene units) and orientation in the
 * scene's frame; the quaternion must be a unit one (to 1e-3). */
Eigen::Isometry3d parseCameraPose(const std::string& option, const std::string& text) {
  const std::vector<double> v = parseNumbers(option, text);
  if (v.size() != 3 && v.size() != 7)
    throw UsageError(option + ": '" + text +
                     "' is not X,Y,Z or X,Y,Z,QW,QX,QY,QZ (the camera's position and "
                     "orientation in the scene's frame)");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  if (v.size() == 7) {
    const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
    if (!(std::abs(q.norm() - 1.0) < 1e-3))
      throw UsageError(option + ": the quaternion (" + std::to_string(v[3]) + ", " +
                       std::to_string(v[4]) + ", " + std::to_string(v[5]) + ", " +
                       std::to_string(v[6]) + ") has norm " + std::to_string(q.norm()) +
                       ", not 1: not a rotation");
    pose.linear() = q.normalized().toRotationMatrix();
  }
  return pose;
}

/** "FX,FY,CX,CY": a pinhole camera's focal lengths (> 0) and principal point, pixels. */
Eigen::Vector4d parseIntrinsics(const std::string& option, const std::string& text) {
  const std::vector<double> v = parseNumbers(option, text);
  if (v.size() != 4 || !(v[0] > 0.0 && v[1] > 0.0))
    throw UsageError(option + ": '" + text +
                     "' is not FX,FY,CX,CY (focal lengths > 0 and the principal point, pixels)");
  return {v[0], v[1], v[2], v[3]};
}

pcl::icf::SearchStrategy parseStrategy(const std::string& option, const std::string& text) {
  try {
    return pcl::icf::parseSearchStrategy(text);
  } catch (const std::invalid_argument&) {
    throw UsageError(option + ": '" + text + "' is not a strategy (fast or thesis)");
  }
}

/** --set NAME=VALUE[,NAME=VALUE...]: registered fields (localizerFields(), the Python keywords'
 * names) set from text. \throws UsageError naming the field. */
void setRegisteredFields(const std::string& option, const std::string& text,
                         pcl::icf::localization::LocalizerParams& p) {
  for (const std::string& kv : pcl_icf_tools::splitComma(text)) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos)
      throw UsageError(option + ": '" + kv + "' is not NAME=VALUE");
    try {
      const auto& field =
          pcl::icf::findField(pcl::icf::localization::localizerFields(), kv.substr(0, eq));
      pcl::icf::setFieldText(field, p, kv.substr(eq + 1));
    } catch (const std::invalid_argument& e) {
      throw UsageError(option + ": " + e.what());
    }
  }
}

/** The localizer's options (segmentation, search, colour, acceptance): true when \a a is one,
 * its value read from \a args into \a p. \throws UsageError for a bad value. */
bool parseLocalizerOption(const std::string& a, ArgumentReader& args,
                          pcl::icf::localization::LocalizerParams& p) {
  if (a == "--no-segment") {
    args.noValue(a);
    p.segment = false;
  } else if (a == "--strategy")
    p.strategy = parseStrategy(a, args.value(a));
  else if (a == "--fallback") {
    const std::string v = args.value(a);
    try {
      p.fallback = pcl::icf::parseFallbackPolicy(v);
    } catch (const std::invalid_argument&) {
      throw UsageError(a + ": '" + v + "' is not off, auto or always");
    }
  } else if (a == "--seed")
    p.seed = parseSeed(a, args.value(a));
  else if (a == "--threads") {
    const int t = static_cast<int>(parseInteger(a, args.value(a), 0, 1024));
    p.threads = t;
  } else if (a == "--color" || a == "--colour") {
    const std::string v = args.value(a);
    if (v == "none")
      p.colour.expected.reset();
    else
      p.colour.expected = parseColour(a, v);
  } else if (a == "--color-weight" || a == "--colour-weight")
    p.colour.weight = parseNumber(a, args.value(a));
  else if (a == "--cluster-tolerance")
    p.cluster.tolerance = parsePositive(a, args.value(a));
  else if (a == "--min-cluster-size")
    p.cluster.min_size = static_cast<std::size_t>(parseInteger(a, args.value(a), 1, 100000000));
  else if (a == "--inlier-distance")
    p.tuning().icf.acceptance.inlier_distance = static_cast<float>(parsePositive(a, args.value(a)));
  else if (a == "--min-coverage")
    p.tuning().icf.acceptance.min_surface_coverage = parseFraction(a, args.value(a));
  else if (a == "--max-rmse")
    p.tuning().icf.acceptance.max_rmse = parsePositive(a, args.value(a));
  else if (a == "--gate-distance")
    p.tuning().icf.acceptance.gate.distance = static_cast<float>(parsePositive(a, args.value(a)));
  else if (a == "--gate-max-far")
    p.tuning().icf.acceptance.gate.max_points =
        static_cast<int>(parseInteger(a, args.value(a), 0, 100000000));
  else if (a == "--no-gate") {
    args.noValue(a);
    p.tuning().icf.acceptance.gate.enabled = false;
  } else if (a == "--gate") {
    args.noValue(a);
    p.tuning().icf.acceptance.gate.enabled = true;
  } else if (a == "--min-confidence") {
    p.min_confidence = parseFraction(a, args.value(a));
  } else if (a == "--max-instances")
    p.max_instances = static_cast<int>(parseInteger(a, args.value(a), 1, 1000));
  else
    return false;
  return true;
}

/** Appends --models LIST's entries ("MODEL [COUNT]" a line, '#' comments, paths relative to
 * the list's folder) to \a models and their counts (\a default_count where none is given) to
 * \a counts. \throws UsageError. */
void readModelList(const std::string& list, int default_count, std::vector<std::string>& models,
                   std::vector<int>& counts) {
  std::ifstream in(list);
  if (!in)
    throw UsageError("--models " + list + ": cannot be read");
  const std::filesystem::path folder = std::filesystem::path(list).parent_path();
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    line = line.substr(0, line.find('#'));
    std::istringstream fields(line);
    std::string path, count, extra;
    if (!(fields >> path))
      continue;
    const std::string where = "--models " + list + " line " + std::to_string(number);
    int n = default_count;
    if (fields >> count)
      n = static_cast<int>(parseInteger(where, count, 1, 1000));
    if (fields >> extra)
      throw UsageError(where + ": expected MODEL [COUNT], got more");
    const std::filesystem::path p(path);
    models.push_back(p.is_absolute() ? path : (folder / p).string());
    counts.push_back(n);
  }
  if (models.empty())
    throw UsageError("--models " + list + ": no model listed");
}

/** The mode (one scene, --batch or --track) from the positional arguments, and the options
 * that belong to another mode refused. \throws UsageError. */
void checkMode(ToolOptions& o, const std::vector<std::string>& positional, bool idle_given) {
  if (!o.prepare.empty() || !o.prepare_output.empty()) {
    if (o.prepare.empty() || o.prepare_output.empty())
      throw UsageError("--prepare MODEL and -o FILE go together");
    if (!positional.empty() || !o.track.empty() || !o.batch.empty() || !o.models_list.empty() ||
        !o.json.empty() || !o.output.empty() || !o.render.empty() || o.view || o.no_cache)
      throw UsageError("--prepare MODEL -o FILE takes no scene, other model or output");
    return;
  }
  if (!o.depth_png.rgb.empty() && (!o.track.empty() || !o.batch.empty()))
    throw UsageError("--rgb names one scene's colour image: not for --batch or --track");
  if (!o.models_list.empty() && (!o.track.empty() || !o.batch.empty()))
    throw UsageError(
        "--models is for one scene; --track and --batch take their MODELs as "
        "arguments");
  if (!o.track.empty()) {
    if (positional.empty() || !o.batch.empty() || !o.out_dir.empty() || !o.json.empty() ||
        !o.output.empty() || !o.render.empty() || o.view || o.render_all || o.output_all)
      throw UsageError("--track FRAMES takes one or more MODELs and no other input or output");
    o.models = positional;
    if (idle_given && !o.follow)
      throw UsageError("--idle-seconds is for --follow");
    if (o.idle_seconds > 86400.0)
      throw UsageError("--idle-seconds: at most 86400 (a day)");
  } else if (!o.render_dir.empty() || o.follow || idle_given) {
    throw UsageError("--render-dir, --follow and --idle-seconds need --track FRAMES");
  } else if (!o.batch.empty()) {
    if (positional.size() != 1)
      throw UsageError("--batch SCENES takes exactly one MODEL argument, got " +
                       std::to_string(positional.size()));
    o.model = positional[0];
    if (o.out_dir.empty())
      throw UsageError("--batch needs --out-dir DIR for its JSON files");
    if (!o.json.empty() || !o.output.empty() || !o.render.empty() || o.view)
      throw UsageError(
          "--json, --output, --render and --view are for one scene; with --batch "
          "use --out-dir, --render-all and --output-all");
  } else {
    if (positional.empty() || (positional.size() < 2 && o.models_list.empty()))
      throw UsageError("expected SCENE and MODEL (see -h)");
    o.scene = positional[0];
    if (!o.out_dir.empty() || o.render_all || o.output_all)
      throw UsageError("--out-dir, --render-all and --output-all need --batch");
    o.models.assign(positional.begin() + 1, positional.end());
    o.model_counts.assign(o.models.size(), o.params.max_instances);
    if (!o.models_list.empty())
      readModelList(o.models_list, o.params.max_instances, o.models, o.model_counts);
    if (o.models.size() == 1) {
      o.model = o.models.front();
      o.params.max_instances = o.model_counts.front();
      o.models.clear();
      o.model_counts.clear();
    } else if (!o.output.empty()) {
      throw UsageError("--output takes one MODEL; for several, --json and --render");
    } else if (o.params.colour.expected) {
      throw UsageError("--color describes one object: give one MODEL with it");
    }
  }
}

}  // namespace

ToolOptions parseToolOptions(int argc, const char* const* argv) {
  ToolOptions o;
  auto& p = o.params;
  std::vector<std::string> positional;
  bool idle_given = false;
  std::optional<std::size_t> keep;
  std::vector<std::string> sets;  // --set's, applied last: they win over the options
  ArgumentReader args(argc, argv);
  while (!args.done()) {
    const std::string a = args.next();
    if (a == "-h" || a == "--help") {
      o.help = true;
      return o;
    } else if (a == "--list-fields") {
      args.noValue(a);
      o.list_fields = true;
      return o;
    } else if (parseLocalizerOption(a, args, p))
      continue;
    else if (a == "--keep")
      keep = static_cast<std::size_t>(parseInteger(a, args.value(a), 1, 10000));
    else if (a == "--set")
      sets.push_back(args.value(a));
    else if (a == "--mesh-accuracy")
      p.mesh_accuracy = static_cast<float>(parseNumber(a, args.value(a)));
    else if (a == "--exact-mesh")
      throw UsageError(
          "--exact-mesh is gone: one rule verifies every mesh. A mesh that differs from the "
          "object: --mesh-accuracy M (metres); a simulated camera without low-frequency depth "
          "error: --set depth_systematic=0");
    else if (a == "--units")
      o.units = parseUnits(a, args.value(a));
    else if (a == "--model-units")
      o.model_units = parseUnits(a, args.value(a));
    else if (a == "--camera")
      o.camera = parseCameraPose(a, args.value(a));
    else if (a == "--intrinsics")
      o.depth_png.intrinsics = parseIntrinsics(a, args.value(a));
    else if (a == "--depth-scale")
      o.depth_png.depth_scale = parsePositive(a, args.value(a));
    else if (a == "--rgb")
      o.depth_png.rgb = args.value(a);
    else if (a == "--json")
      o.json = args.value(a);
    else if (a == "--output")
      o.output = args.value(a);
    else if (a == "--render")
      o.render = args.value(a);
    else if (a == "--render-size") {
      const std::string v = args.value(a);
      const auto x = v.find('x');
      if (x == std::string::npos)
        throw UsageError(a + ": '" + v + "' is not WIDTHxHEIGHT");
      o.render_width = static_cast<int>(parseInteger(a, v.substr(0, x), 64, 8192));
      o.render_height = static_cast<int>(parseInteger(a, v.substr(x + 1), 64, 8192));
    } else if (a == "--render-color" || a == "--render-colour")
      o.render_colour = parseColour(a, args.value(a));
    else if (a == "--view") {
      args.noValue(a);
      o.view = true;
    } else if (a == "--no-cache") {
      args.noValue(a);
      o.no_cache = true;
    } else if (a == "--force" || a == "-f") {
      args.noValue(a);
      o.force = true;
    } else if (a == "--quiet" || a == "-q") {
      args.noValue(a);
      o.quiet = true;
    } else if (a == "--verbose" || a == "-v") {
      args.noValue(a);
      o.verbose = true;
    } else if (a == "--batch")
      o.batch = args.value(a);
    else if (a == "--track")
      o.track = args.value(a);
    else if (a == "--render-dir")
      o.render_dir = args.value(a);
    else if (a == "--follow") {
      args.noValue(a);
      o.follow = true;
    } else if (a == "--idle-seconds") {
      o.idle_seconds = parsePositive(a, args.value(a));
      idle_given = true;
    } else if (a == "--models")
      o.models_list = args.value(a);
    else if (a == "--prepare")
      o.prepare = args.value(a);
    else if (a == "-o")
      o.prepare_output = args.value(a);
    else if (a == "--out-dir")
      o.out_dir = args.value(a);
    else if (a == "--render-all") {
      args.noValue(a);
      o.render_all = true;
    } else if (a == "--output-all") {
      args.noValue(a);
      o.output_all = true;
    } else if (isOption(a))
      throw UsageError("unknown option " + a + " (see -h)");
    else
      positional.push_back(a);
  }

  checkMode(o, positional, idle_given);
  if (keep)
    p.tuning().icf.tuning().global.keep = *keep;
  for (const std::string& text : sets)
    setRegisteredFields("--set", text, p);
  if (p.colour.expected && !(p.colour.weight >= 0.0))
    throw UsageError("--color-weight must be >= 0");
  try {
    p.validate();
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("invalid parameter: ") + e.what());
  }
  return o;
}

std::string usageText(const std::string& program) {
  const ToolOptions d;
  const auto& p = d.params;
  std::ostringstream u;
  u << "Finds the 6D pose of a CAD mesh in a depth scan by Iterative Closest Face.\n"
    << "\n"
    << "Syntax is: " << program << " SCENE MODEL <options>\n"
    << "       or: " << program << " SCENE MODEL MODEL... | --models LIST <options>\n"
    << "       or: " << program << " --batch SCENES MODEL --out-dir DIR <options>\n"
    << "       or: " << program << " --prepare MODEL -o FILE.icfmodel [--model-units U]\n"
    << "  SCENE  a point cloud: .pcd, .ply, or .xyz/.asc (one \"x y z\" per line), or a\n"
    << "         16-bit depth image .png (BOP's), with --intrinsics and --depth-scale\n"
    << "  MODEL  the object's mesh: .ply, .obj, .stl or .vtk, or a prepared model\n"
    << "         (.icfmodel, see --prepare); with several, every one is searched for in\n"
    << "         one pass and each scene point explains one pose at most\n"
    << "    --models LIST            = more MODELs, from a file: \"MODEL [COUNT]\" a line\n"
    << "                               (COUNT: at most that many instances, default\n"
    << "                               --max-instances;\n"
    << "                               paths relative to the file's folder, '#' comments)\n"
    << "    --prepare MODEL -o FILE  = prepare MODEL once (its closest-point field and point\n"
    << "                               pair table) and write it, with its mesh, to\n"
    << "                               FILE.icfmodel, which loads in milliseconds\n"
    << "  where options are:\n"
    << "  Input:\n"
    << "    --no-cache               = prepare every model afresh: read and write no\n"
    << "                               prepared-model cache (default: "
    << "$XDG_CACHE_HOME/pcl_icf,\n"
    << "                               else ~/.cache/pcl_icf)\n"
    << "    --intrinsics FX,FY,CX,CY = a depth PNG SCENE's camera (pixels; BOP's cam_K)\n"
    << "    --depth-scale S          = a depth PNG SCENE's unit in millimetres (BOP's\n"
    << "                               depth_scale: 0.1 for YCB-Video, 1 for most)\n"
    << "    --rgb FILE.png           = a depth PNG SCENE's colour image (same size)\n"
    << "    --units m|mm|auto        = the scene's units (default: auto, millimetres when the\n"
    << "                               scene spans more than 20 units)\n"
    << "    --model-units m|mm|auto  = the mesh's units (default: auto, millimetres when the\n"
    << "                               mesh spans more than 2 units)\n"
    << "    --no-segment             = the cloud is one object: no table segmentation\n"
    << "    --camera X,Y,Z[,QW,QX,QY,QZ] = the camera's pose in the scene's frame (scene units;\n"
    << "                               camera x right, y down, z forward) for a cloud in a\n"
    << "                               robot's frame (default: the file's VIEWPOINT)\n"
    << "  Search (lengths in metres, whatever the files' units):\n"
    << "    --strategy fast|thesis   = the pose search (default: " << pcl::icf::toString(p.strategy)
    << ")\n"
    << "    --fallback off|auto|always = the SampleConsensus (FPFH) alignment: auto tries it\n"
    << "                               when the search's pose is rejected (default: "
    << pcl::icf::toString(p.fallback) << ")\n"
    << "    --seed N                 = random seed; same seed, same result (default: " << p.seed
    << ")\n"
    << "    --threads N              = threads, 0 for all cores (default: " << p.threads << ")\n"
    << "    --color R,G,B|#rrggbb|none = the object's colour, ranks clusters by colour\n"
    << "                               (default: none)\n"
    << "    --color-weight W         = weight of the colour cue (default: " << p.colour.weight
    << ")\n"
    << "    --cluster-tolerance D    = gap that separates objects (default: " << p.cluster.tolerance
    << ")\n"
    << "    --min-cluster-size N     = smallest object, in points (default: " << p.cluster.min_size
    << ")\n"
    << "  Acceptance:\n"
    << "    --inlier-distance D      = scene points this near the model are inliers (default: "
    << p.tuning().icf.acceptance.inlier_distance << ")\n"
    << "    --min-coverage F         = share of the model's visible surface the scan must\n"
    << "                               cover (default: "
    << p.tuning().icf.acceptance.min_surface_coverage << ")\n"
    << "    --max-rmse D             = RMS distance of the inliers (default: "
    << p.tuning().icf.acceptance.max_rmse << ")\n"
    << "    --gate                   = also apply the thesis's gate (default: off)\n"
    << "    --gate-distance D        = the gate: a cluster where more than max(N, "
    << 100.0 * p.tuning().icf.acceptance.gate.max_fraction << "% of its points)\n"
    << "                               lie farther than D from the posed model is rejected\n"
    << "                               (default: " << p.tuning().icf.acceptance.gate.distance
    << ")\n"
    << "    --gate-max-far N         = that N (default: "
    << p.tuning().icf.acceptance.gate.max_points << ")\n"
    << "    --no-gate                = turn the thesis's gate off\n"
    << "    --min-confidence C       = accept a pose whose verification confidence reaches C\n"
    << "                               (default: " << p.min_confidence << ")\n"
    << "    --keep N                 = search hypotheses refined per cluster (default: "
    << p.tuning().icf.tuning().global.keep << "; more find more partly hidden\n"
    << "                               targets on a cluttered desk, and more look-alikes)\n"
    << "    --mesh-accuracy M        = how far the mesh's surface may lie from the object's,\n"
    << "                               metres (default: " << p.mesh_accuracy
    << ": a CAD model or an accurate\n"
    << "                               scan); a coarser mesh is forgiven that much misfit\n"
    << "    --max-instances N        = report up to N instances of the object, best first,\n"
    << "                               each scene point in one at most (default: "
    << p.max_instances << ")\n"
    << "    --set NAME=V[,NAME=V...] = any registered field, by its Python keyword's name\n"
    << "                               (calibration constants included; --list-fields)\n"
    << "    --list-fields            = print every registered field: kind, range, default, doc\n"
    << "  Output:\n"
    << "    --json FILE              = the result as JSON (poses in the scene's units)\n"
    << "    --output FILE.ply        = the model moved to its pose, in the scene's units\n"
    << "    --render FILE.png        = picture of the scene with the posed model, from the\n"
    << "                               camera (no display needed: xvfb-run when DISPLAY is unset)\n"
    << "    --render-size WxH        = picture size (default: an organized scene's own size\n"
    << "                               scaled to about 640 wide, else 800x600)\n"
    << "    --render-color R,G,B     = the model's colour in pictures (default: 26,255,51)\n"
    << "    --view                   = open a viewer; click a point to print its coordinates\n"
    << "    -f, --force              = replace existing output files (inputs never)\n"
    << "    -q, --quiet              = print nothing but errors\n"
    << "    -v, --verbose            = also show PCL's and VTK's own messages\n"
    << "  Batch:\n"
    << "    --batch SCENES           = a directory of scenes, or a text file listing them\n"
    << "    --out-dir DIR            = writes DIR/<scene>.json for each, and DIR/summary.json\n"
    << "    --render-all             = also DIR/<scene>.png\n"
    << "    --output-all             = also DIR/<scene>.ply for each pose found\n"
    << "  Tracking (" << program << " --track FRAMES MODEL...):\n"
    << "    --track FRAMES           = follow every MODEL over a directory or list of frames;\n"
    << "                               one JSON line per frame on stdout\n"
    << "    --render-dir DIR         = also DIR/NNNN_<frame>.png per frame with the tracked\n"
    << "                               poses drawn (xvfb-run when DISPLAY is unset)\n"
    << "    --follow                 = FRAMES is a folder: track each new frame as it appears\n"
    << "                               (name order, once its size has settled)\n"
    << "    --idle-seconds N         = --follow stops after N s without a new frame (default: "
    << d.idle_seconds << ")\n"
    << "\n"
    << "Exit status: 0 object found, 1 nothing accepted, 2 bad usage or bad input.\n"
    << "In batch mode: 2 if any scene could not be read, else 1 if any scene had no object.\n";
  return u.str();
}

}  // namespace pcl_icf_tool
