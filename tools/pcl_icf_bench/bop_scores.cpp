/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "bop_scores.h"

#include <pcl/icf/evaluation/average_distance.h>
#include <pcl/icf/evaluation/bop_recall.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

namespace pcl_icf_bench {

namespace {

namespace eval = pcl::icf::evaluation;

/** The suites' rule (tools/pcl_icf_bench/bench_report.h): centre within this, ADD-S below this
 * share of the diameter. */
constexpr double kRuleCentreMm = 10.0;
constexpr double kRuleAddS = 0.1;
/** ADD(-S) counts a pose right below this share of the diameter (Hinterstoisser et al.). */
constexpr double kAddThreshold = 0.1;

/** One object's match groups, one per target, for each error. */
struct ObjectGroups {
  std::vector<std::vector<eval::MatchGroup>> vsd;  ///< per VSD tau
  std::vector<eval::MatchGroup> mssd, mspd, add, rule;
};

struct Scores {
  std::size_t instances = 0;
  double vsd = 0.0, mssd = 0.0, mspd = 0.0, add = 0.0, rule = 0.0;
  double ar() const { return (vsd + mssd + mspd) / 3.0; }
};

Eigen::Isometry3d inMetres(Eigen::Isometry3d pose) {
  pose.translation() /= 1000.0;
  return pose;
}

/** The distance image of \a obj rendered at \a pose (mm) in an image of \a camera. */
eval::DepthMap renderedDistances(const BopObject& obj, const Eigen::Isometry3d& pose,
                                 const pcl::icf::io::BopCamera& camera, int width, int height) {
  return eval::distanceImage(eval::renderDepth(*obj.model, inMetres(pose), camera.K, width, height),
                             camera.K);
}

}  // namespace

std::string bopScoresTable(BopBenchData& data, const std::vector<BopEstimate>& rows,
                           const BopScoreParams& params) {
  const std::vector<double> fractions = eval::bopFractions();
  const std::vector<double> mspd_th = eval::bopMspdThresholds(data.camera().width);
  std::map<std::pair<BopImage, int>, std::vector<const BopEstimate*>> estimates;
  for (const BopEstimate& e : rows)
    estimates[{{e.scene_id, e.im_id}, e.obj_id}].push_back(&e);
  std::map<int, std::vector<Eigen::Vector3d>> points_m;  // the vertices in metres
  for (const auto& [id, obj] : data.objects())
    for (const auto& v : obj.vertices)
      points_m[id].push_back(v / 1000.0);

  std::map<int, ObjectGroups> groups;
  for (const auto& [image, targets] : data.targets()) {
    const BopImageTruth& truth = data.truth(image);
    const eval::DepthMap depth = depthOf(*data.cloud(image));
    const eval::DepthMap test = eval::distanceImage(depth, truth.camera.K);
    for (const auto& t : targets) {
      const BopObject& obj = data.objects().at(t.obj_id);
      const double d = obj.diameter_mm;
      std::vector<std::size_t> instances;
      for (std::size_t g = 0; g < truth.gt.size(); ++g)
        if (truth.gt[g].obj_id == t.obj_id)
          instances.push_back(g);
      eval::MatchGroup base;
      base.max_estimates = static_cast<std::size_t>(t.inst_count);
      const std::vector<const BopEstimate*>& found = estimates[{image, t.obj_id}];
      std::vector<eval::DepthMap> gt_renders;  // only where there is an estimate to compare
      for (const std::size_t g : instances) {
        base.gt_valid.push_back(truth.visib[g] >= params.visib_gt_min);
        if (!found.empty())
          gt_renders.push_back(renderedDistances(obj, truth.gt[g].model_to_camera, truth.camera,
                                                 depth.width, depth.height));
      }
      ObjectGroups& og = groups[t.obj_id];
      std::vector<eval::MatchGroup> vsd(fractions.size(), base);
      eval::MatchGroup mssd = base, mspd = base, add = base, rule = base;
      for (const BopEstimate* e : found) {
        const eval::DepthMap est_render =
            renderedDistances(obj, e->pose, truth.camera, depth.width, depth.height);
        std::vector<eval::MatchGroup::Estimate> ev(fractions.size(), {e->score, {}});
        eval::MatchGroup::Estimate es{e->score, {}}, ep = es, ea = es, er = es;
        for (std::size_t i = 0; i < instances.size(); ++i) {
          const Eigen::Isometry3d& gt = truth.gt[instances[i]].model_to_camera;
          es.errors.push_back(eval::mssd(e->pose, gt, obj.vertices, obj.symmetries) / d);
          ep.errors.push_back(
              eval::mspd(e->pose, gt, truth.camera.K, obj.vertices, obj.symmetries));
          ea.errors.push_back((obj.symmetric() ? eval::adi(e->pose, gt, obj.vertices)
                                               : eval::add(e->pose, gt, obj.vertices)) /
                              d);
          const double centre = (e->pose * obj.box_centre - gt * obj.box_centre).norm();
          const double surface_mm =
              1000.0 * eval::addSToSurface(*obj.model, inMetres(e->pose), inMetres(gt),
                                           points_m.at(t.obj_id));
          // Right (< 1) when both parts of the rule hold.
          er.errors.push_back(std::max(centre / kRuleCentreMm, surface_mm / (kRuleAddS * d)));
          const std::vector<double> v = eval::vsdFromDistances(
              test, est_render, gt_renders[i], params.vsd_delta_mm / 1000.0, fractions, d / 1000.0);
          for (std::size_t k = 0; k < fractions.size(); ++k)
            ev[k].errors.push_back(v[k]);
        }
        mssd.estimates.push_back(es);
        mspd.estimates.push_back(ep);
        add.estimates.push_back(ea);
        rule.estimates.push_back(er);
        for (std::size_t k = 0; k < fractions.size(); ++k)
          vsd[k].estimates.push_back(ev[k]);
      }
      og.vsd.resize(fractions.size());
      for (std::size_t k = 0; k < fractions.size(); ++k)
        og.vsd[k].push_back(vsd[k]);
      og.mssd.push_back(mssd);
      og.mspd.push_back(mspd);
      og.add.push_back(add);
      og.rule.push_back(rule);
    }
  }

  const auto scoresOf = [&](const std::set<int>& ids) {
    ObjectGroups all;
    all.vsd.resize(fractions.size());
    for (const int id : ids) {
      const ObjectGroups& og = groups[id];
      const auto append = [](std::vector<eval::MatchGroup>& to,
                             const std::vector<eval::MatchGroup>& from) {
        to.insert(to.end(), from.begin(), from.end());
      };
      append(all.mssd, og.mssd);
      append(all.mspd, og.mspd);
      append(all.add, og.add);
      append(all.rule, og.rule);
      for (std::size_t k = 0; k < og.vsd.size(); ++k)
        append(all.vsd[k], og.vsd[k]);
    }
    Scores s;
    for (const auto& g : all.mssd)
      s.instances +=
          static_cast<std::size_t>(std::count(g.gt_valid.begin(), g.gt_valid.end(), true));
    s.mssd = eval::averageRecall(all.mssd, fractions);
    s.mspd = eval::averageRecall(all.mspd, mspd_th);
    for (const auto& per_tau : all.vsd)
      s.vsd += eval::averageRecall(per_tau, fractions) / static_cast<double>(all.vsd.size());
    s.add = eval::recall(all.add, kAddThreshold);
    s.rule = eval::recall(all.rule, 1.0);
    return s;
  };
  std::ostringstream md;
  md << "| object | instances | AR_VSD | AR_MSSD | AR_MSPD | AR | ADD(-S) | rule |\n"
     << "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  char line[200];
  std::set<int> all;
  const auto write = [&](const std::string& name, const Scores& s, const char* bold) {
    std::snprintf(line, sizeof line, "| %s | %zu | %.3f | %.3f | %.3f | %s%.3f%s | %.3f | %.3f |\n",
                  name.c_str(), s.instances, s.vsd, s.mssd, s.mspd, bold, s.ar(), bold, s.add,
                  s.rule);
    md << line;
  };
  for (const auto& [id, obj] : data.objects()) {
    all.insert(id);
    write(std::to_string(id), scoresOf({id}), "");
  }
  write("all", scoresOf(all), "**");
  return md.str();
}

}  // namespace pcl_icf_bench
