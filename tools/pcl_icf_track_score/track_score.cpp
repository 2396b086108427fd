/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// pcl_icf_track_score: scores pcl_icf_tool --track's JSON lines against the ground truth of
// pcl_icf_make_dataset --kind sequence (the tracking bars, doc/BENCHMARKS.md "Tracking").
//
//   pcl_icf_track_score [--poses NAME] [--min-visible F] SEQDIR...
//
// Reads SEQDIR/truth.json and SEQDIR/NAME (default poses.jsonl: the tool's stdout for
// SEQDIR/frames.txt) and prints a markdown table, one row per sequence and tracked object:
//   accurate  frames with a pose within 1 cm / 5 deg (symmetry-aware, synthetic::poseError) over
//   the
//             frames the object is present and at least F (default 0.5) visible
//   hidden    the same over the present frames it is less visible (not a bar; each pose given
//             there beyond 1 cm / 5 deg is listed after the table)
//   absent    frames with a pose while it is off the table (the bar: 0)
//   loss      frames from its removal to the first frame without a pose (bar: < 3)
//   re-found  frames from its return to the first frame with an accurate pose (bar: < 5)
//   refine    median refine_ms of the frames it was tracked; frame: median ms of the frames
// then the totals and whether the bars are met. Exit codes: 0 bars met, 1 not met, 2 bad input.
#include "common/arguments.h"
#include "pcl_icf_bench/bench_manifest.h"
#include "synthetic/pose_error.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
namespace t = pcl::icf::synthetic;
using json = nlohmann::json;
using pcl_icf_tools::bench::BadInput;

constexpr double kMaxTranslation = 0.01;  // metres
constexpr double kMaxRotationDeg = 5.0;
constexpr int kLossBar = 3, kRefoundBar = 5;  // frames, exclusive

struct Score {
  std::string sequence, object;
  int scored = 0, accurate = 0;      ///< present, visible >= min_visible
  int hidden = 0, hidden_ok = 0;     ///< present, less visible
  int absent = 0, absent_posed = 0;  ///< off the table
  std::vector<int> loss, refound;    ///< delays per removal / return; -1: never
  std::vector<double> refine_ms;
  std::vector<std::string> misses;  ///< the scored frames off by more than the bar, and why
  /** The less visible frames with a pose off by more than the bar (a wrong pose given). */
  std::vector<std::string> hidden_off;
};

json readJson(const fs::path& path) {
  std::ifstream in(path);
  if (!in)
    throw BadInput(path.string() + ": cannot read");
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw BadInput(path.string() + ": not JSON: " + e.what());
  }
}

Eigen::Isometry3d poseOf(const json& rows, const std::string& where) {
  if (!rows.is_array() || rows.size() != 4)
    throw BadInput(where + ": a pose is 4 rows of 4 numbers");
  Eigen::Isometry3d pose;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      pose.matrix()(r, c) = rows.at(r).at(c).get<double>();
  return pose;
}

std::string fixed(double v, int digits) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.*f", digits, v);
  return text;
}

double median(std::vector<double> v) {
  if (v.empty())
    return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/** The tool's lines by frame index; frames with "error" hold no objects. */
std::map<int, json> readPoses(const fs::path& path) {
  std::ifstream in(path);
  if (!in)
    throw BadInput(path.string() + ": cannot read (the output of pcl_icf_tool --track)");
  std::map<int, json> lines;
  int number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    try {
      json j = json::parse(line);
      const int frame = j.at("frame").get<int>();
      lines[frame] = std::move(j);
    } catch (const json::exception& e) {
      throw BadInput(path.string() + ":" + std::to_string(number) + ": " + e.what());
    }
  }
  return lines;
}

std::vector<Score> scoreSequence(const fs::path& dir, const std::string& poses_name,
                                 double min_visible, std::vector<double>& frame_ms) {
  const json truth = readJson(dir / "truth.json");
  const std::map<int, json> lines = readPoses(dir / poses_name);
  std::vector<Score> scores;
  try {
    for (const auto& o : truth.at("objects")) {
      if (!o.at("tracked").get<bool>())
        continue;
      const std::string name = o.at("name").get<std::string>();
      const t::Symmetry symmetry = pcl_icf_tools::bench::parseSymmetry(
          o.at("symmetry").get<std::string>(), (dir / "truth.json").string());
      Score s;
      s.sequence = dir.filename().string();
      s.object = name;
      int removed_at = -1, back_at = -1;
      bool was_present = true;
      for (const auto& frame : truth.at("frames")) {
        const int f = frame.at("frame").get<int>();
        const json* gt = nullptr;
        for (const auto& g : frame.at("objects"))
          if (g.at("name") == name)
            gt = &g;
        if (!gt)
          throw BadInput((dir / "truth.json").string() + ": frame " + std::to_string(f) +
                         " does not list " + name);
        const json* est = nullptr;
        const auto line = lines.find(f);
        if (line != lines.end() && line->second.contains("objects"))
          for (const auto& e : line->second.at("objects"))
            if (e.at("name") == name)
              est = &e;
        const bool posed = est && !est->at("pose").is_null();
        bool ok = false;
        std::string off = est ? est->at("state").get<std::string>() + ", no pose" : "no line";
        if (posed) {
          const t::PoseError error =
              t::poseError(poseOf(est->at("pose"), name), poseOf(gt->at("pose"), name), symmetry);
          ok = error.translation <= kMaxTranslation && error.rotation_deg <= kMaxRotationDeg;
          off = est->at("state").get<std::string>() + ", " + fixed(1e3 * error.translation, 1) +
                " mm, " + fixed(error.rotation_deg, 1) + " deg";
          if (est->at("state") == "tracking")
            s.refine_ms.push_back(est->at("refine_ms").get<double>());
        }
        const bool present = gt->at("present").get<bool>();
        if (!present) {
          ++s.absent;
          s.absent_posed += posed;
          if (was_present) {
            removed_at = f;
            s.loss.push_back(-1);
          }
          if (!posed && removed_at >= 0 && s.loss.back() < 0)
            s.loss.back() = f - removed_at;
        } else {
          if (!was_present) {
            back_at = f;
            s.refound.push_back(-1);
          }
          if (ok && back_at >= 0 && s.refound.back() < 0)
            s.refound.back() = f - back_at;
          const double visible = gt->at("visible").get<double>();
          if (visible >= min_visible) {
            ++s.scored;
            s.accurate += ok;
            if (!ok)
              s.misses.push_back(s.sequence + " " + name + " frame " + std::to_string(f) +
                                 " (visible " + fixed(visible, 2) + "): " + off);
          } else {
            ++s.hidden;
            s.hidden_ok += ok;
            if (posed && !ok)
              s.hidden_off.push_back(s.sequence + " " + name + " frame " + std::to_string(f) +
                                     " (visible " + fixed(visible, 2) + "): " + off);
          }
        }
        was_present = present;
      }
      scores.push_back(s);
    }
    for (const auto& [f, line] : lines)
      if (line.contains("ms"))
        frame_ms.push_back(line.at("ms").get<double>());
  } catch (const json::exception& e) {
    throw BadInput((dir / "truth.json").string() + ": " + e.what());
  }
  return scores;
}

std::string delays(const std::vector<int>& d) {
  std::string text;
  for (int v : d)
    text += (text.empty() ? "" : ", ") + (v < 0 ? std::string("never") : std::to_string(v));
  return text.empty() ? "-" : text;
}

bool within(const std::vector<int>& d, int bar) {
  return std::all_of(d.begin(), d.end(), [bar](int v) { return v >= 0 && v < bar; });
}

int usage() {
  std::fprintf(
      stderr,
      "Usage: pcl_icf_track_score [--poses NAME] [--min-visible F] SEQDIR...\n"
      "Scores SEQDIR/NAME (default poses.jsonl, pcl_icf_tool --track's output) against\n"
      "SEQDIR/truth.json (pcl_icf_make_dataset --kind sequence). Exit 0: the bars met\n"
      "(99%% of the frames accurate, lost and re-found within a few frames, no pose while\n"
      "absent), 1: not met, 2: bad input.\n");
  return 2;
}

/** What to score: --poses, --min-visible and the SEQDIRs. */
struct Arguments {
  std::string poses_name = "poses.jsonl";
  double min_visible = 0.5;
  std::vector<fs::path> dirs;
};

/** \throws pcl_icf_tools::UsageError for an unknown option or a bad value. */
Arguments parseArguments(int argc, char** argv) {
  Arguments parsed;
  pcl_icf_tools::ArgumentReader args(argc, argv);
  while (!args.done()) {
    const std::string a = args.next();
    if (a == "--poses") {
      parsed.poses_name = args.value(a);
    } else if (a == "--min-visible") {
      const std::string v = args.value(a);
      try {
        parsed.min_visible = pcl_icf_tools::parseFraction(a, v);
      } catch (const pcl_icf_tools::UsageError&) {
        throw pcl_icf_tools::UsageError(a + ": '" + v + "' is not in [0, 1]");
      }
    } else if (a.rfind("-", 0) == 0) {
      throw pcl_icf_tools::UsageError("unknown option or missing value: " + a);
    } else {
      parsed.dirs.emplace_back(a);
    }
  }
  return parsed;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments parsed;
  try {
    parsed = parseArguments(argc, argv);
  } catch (const pcl_icf_tools::UsageError& e) {
    std::fprintf(stderr, "pcl_icf_track_score: %s\n", e.what());
    return usage();
  }
  const std::string& poses_name = parsed.poses_name;
  const double min_visible = parsed.min_visible;
  const std::vector<fs::path>& dirs = parsed.dirs;
  if (dirs.empty())
    return usage();
  try {
    std::vector<Score> all;
    std::vector<double> frame_ms;
    for (const auto& d : dirs)
      for (auto& s : scoreSequence(d, poses_name, min_visible, frame_ms))
        all.push_back(std::move(s));
    std::printf(
        "| sequence | object | accurate (visible >= %.0f%%) | hidden: accurate | poses while "
        "absent | loss after (frames) | re-found after | refine ms (median) |\n"
        "|---|---|---:|---:|---:|---:|---:|---:|\n",
        100.0 * min_visible);
    Score total;
    bool bars = true;
    for (const auto& s : all) {
      std::printf("| %s | %s | %d/%d | %d/%d | %d/%d | %s | %s | %.1f |\n", s.sequence.c_str(),
                  s.object.c_str(), s.accurate, s.scored, s.hidden_ok, s.hidden, s.absent_posed,
                  s.absent, delays(s.loss).c_str(), delays(s.refound).c_str(), median(s.refine_ms));
      total.scored += s.scored;
      total.accurate += s.accurate;
      total.hidden += s.hidden;
      total.hidden_ok += s.hidden_ok;
      total.absent += s.absent;
      total.absent_posed += s.absent_posed;
      total.loss.insert(total.loss.end(), s.loss.begin(), s.loss.end());
      total.refound.insert(total.refound.end(), s.refound.begin(), s.refound.end());
      total.refine_ms.insert(total.refine_ms.end(), s.refine_ms.begin(), s.refine_ms.end());
      total.misses.insert(total.misses.end(), s.misses.begin(), s.misses.end());
      total.hidden_off.insert(total.hidden_off.end(), s.hidden_off.begin(), s.hidden_off.end());
    }
    const double rate = total.scored ? static_cast<double>(total.accurate) / total.scored : 0.0;
    const bool accurate = rate >= 0.99, lost = within(total.loss, kLossBar),
               refound = within(total.refound, kRefoundBar), clean = total.absent_posed == 0;
    bars = accurate && lost && refound && clean;
    std::printf("| **all** | | **%d/%d (%.1f%%)** | %d/%d | %d/%d | %s | %s | %.1f |\n\n",
                total.accurate, total.scored, 100.0 * rate, total.hidden_ok, total.hidden,
                total.absent_posed, total.absent, delays(total.loss).c_str(),
                delays(total.refound).c_str(), median(total.refine_ms));
    for (const auto& miss : total.misses)
      std::printf("missed: %s\n", miss.c_str());
    for (const auto& off : total.hidden_off)
      std::printf("posed beyond 1 cm / 5 deg while less visible: %s\n", off.c_str());
    std::printf("whole frame: median %.1f ms over %zu frames\n", median(frame_ms), frame_ms.size());
    std::printf(
        "bars: accurate >= 99%%: %s; loss within %d frames: %s; re-found within %d: %s; no pose "
        "while absent: %s\n",
        accurate ? "met" : "NOT met", kLossBar, lost ? "met" : "NOT met", kRefoundBar,
        refound ? "met" : "NOT met", clean ? "met" : "NOT met");
    return bars ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcl_icf_track_score: %s\n", e.what());
    return 2;
  }
}
