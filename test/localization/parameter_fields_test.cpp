// The field registry (parameter_fields.h, localizer_fields.h, tracker_fields.h) against the
// structs' members themselves: a field written through the registry is read back from the
// member it names, and no other field moves (no two names for one member, no name that sets
// nothing); wrong kinds, out-of-range values and unknown names are refused with the field's
// name; every default's text reads back exactly.
#include <pcl/icf/localization/localizer_fields.h>
#include <pcl/icf/tracking/tracker_fields.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using pcl::icf::FieldKind;
using pcl::icf::FieldRegistry;
using pcl::icf::IcfParams;
using pcl::icf::localization::localizerFields;
using pcl::icf::localization::LocalizerParams;
using pcl::icf::tracking::trackerFields;
using pcl::icf::tracking::TrackerParams;

template <typename Params>
std::vector<std::string> texts(const FieldRegistry<Params>& registry, const Params& p) {
  std::vector<std::string> out;
  for (const auto& f : registry)
    out.push_back(pcl::icf::fieldText(f, p));
  return out;
}

/** A value of \a f other than its default, inside its range (a choice: another name). */
template <typename Params>
std::string otherValue(const pcl::icf::ParameterField<Params>& f, const Params& defaults) {
  if (f.kind == FieldKind::Choice) {
    const std::string now = f.get_choice(defaults);
    return *std::find_if(f.choices.begin(), f.choices.end(),
                         [&](const std::string& c) { return c != now; });
  }
  const double now = f.get_number(defaults);
  if (f.kind == FieldKind::Flag)
    return now != 0.0 ? "0" : "1";
  const double hi = std::isinf(f.max) ? f.min + 8.0 : f.max;
  double v = f.min + 0.25 * (hi - f.min);  // 0.25 and 0.375: exact in float and double
  if (f.kind == FieldKind::Count)
    v = std::floor(v);
  if (v == now)
    v = f.kind == FieldKind::Count ? std::min(hi, v + 1.0) : f.min + 0.375 * (hi - f.min);
  return pcl::icf::detail::shortestText(v);
}

/** Every field set alone to another value reads back that value and moves no other field. */
template <typename Params>
void expectEachFieldSetsItselfAlone(const FieldRegistry<Params>& registry) {
  const Params defaults{};
  const std::vector<std::string> before = texts(registry, defaults);
  for (std::size_t i = 0; i < registry.size(); ++i) {
    Params p{};
    const std::string value = otherValue(registry[i], defaults);
    pcl::icf::setFieldText(registry[i], p, value);
    const std::vector<std::string> after = texts(registry, p);
    EXPECT_EQ(after[i], value) << registry[i].name;
    EXPECT_NE(after[i], before[i]) << registry[i].name << " did not move";
    for (std::size_t j = 0; j < registry.size(); ++j) {
      if (j != i) {
        EXPECT_EQ(after[j], before[j])
            << "setting " << registry[i].name << " moved " << registry[j].name;
      }
    }
  }
}

template <typename Params>
std::set<std::string> names(const FieldRegistry<Params>& registry) {
  std::set<std::string> out;
  for (const auto& f : registry)
    out.insert(f.name);
  return out;
}

TEST(FieldRegistry, NamesAreUniqueAndTheTrackersAreItsOwn) {
  EXPECT_EQ(names(pcl::icf::icfFields()).size(), pcl::icf::icfFields().size());
  EXPECT_EQ(names(localizerFields()).size(), localizerFields().size());
  // Python's Tracker takes both lists as one set of keywords.
  for (const auto& name : names(trackerFields())) {
    EXPECT_EQ(names(localizerFields()).count(name), 0u) << name;
  }
}

TEST(FieldRegistry, EachFieldSetsItsMemberAlone) {
  expectEachFieldSetsItselfAlone(pcl::icf::icfFields());
  expectEachFieldSetsItselfAlone(localizerFields());
  expectEachFieldSetsItselfAlone(trackerFields());
}

TEST(FieldRegistry, DefaultsReadBackExactly) {
  LocalizerParams p;
  for (const auto& f : localizerFields())
    pcl::icf::setFieldText(f, p, pcl::icf::fieldText(f, LocalizerParams{}));
  EXPECT_EQ(texts(localizerFields(), p), texts(localizerFields(), LocalizerParams{}));
  // Bit for bit, on members of every type (float, double, size_t, int, bool, enum).
  const LocalizerParams d;
  EXPECT_EQ(p.tuning().icf.acceptance.gate.distance, d.tuning().icf.acceptance.gate.distance);
  EXPECT_EQ(p.tuning().hypotheses.voting.reference_share,
            d.tuning().hypotheses.voting.reference_share);
  EXPECT_EQ(p.tuning().verification.fit_residual, d.tuning().verification.fit_residual);
  EXPECT_EQ(p.cluster.min_size, d.cluster.min_size);
  EXPECT_EQ(p.strategy, d.strategy);
  EXPECT_NO_THROW(p.validate());
}

TEST(FieldRegistry, NamesReachTheMembersTheySay) {
  LocalizerParams p;
  const auto set = [&p](const std::string& name, const std::string& value) {
    pcl::icf::setFieldText(pcl::icf::findField(localizerFields(), name), p, value);
  };
  set("keep", "7");
  set("seed", "12345");
  set("threads", "3");
  set("strategy", "thesis");
  set("cluster_tolerance", "0.03");
  set("fit_residual", "0.9");
  set("pp_kept", "55");
  set("max_points", "640");
  set("far_point_gate", "true");
  set("final_points", "5000");
  set("pp_max_scene_points", "20000");
  set("promising_share", "0.3");
  EXPECT_EQ(p.tuning().icf.tuning().global.keep, 7u);
  EXPECT_EQ(p.seed, 12345u);
  EXPECT_EQ(p.threads, 3);
  EXPECT_EQ(p.strategy, pcl::icf::SearchStrategy::Thesis);
  // The registration is run with the localizer's own seed, threads and strategy.
  EXPECT_EQ(p.icfParams().seed, 12345u);
  EXPECT_EQ(p.icfParams().threads, 3);
  EXPECT_EQ(p.icfParams().strategy, pcl::icf::SearchStrategy::Thesis);
  EXPECT_EQ(p.cluster.tolerance, 0.03);
  EXPECT_EQ(p.segmentationParams().cluster.tolerance, 0.03);
  EXPECT_EQ(p.tuning().verification.fit_residual, 0.9);
  EXPECT_EQ(p.tuning().hypotheses.voting.kept, 55u);
  EXPECT_EQ(p.tuning().icf.tuning().refinement.max_points, 640u);
  EXPECT_TRUE(p.tuning().icf.acceptance.gate.enabled);
  EXPECT_EQ(p.tuning().hypotheses.final_points, 5000u);
  EXPECT_EQ(p.tuning().hypotheses.max_voting_points, 20000u);
  EXPECT_EQ(p.tuning().promising_share, 0.3);

  TrackerParams t;
  pcl::icf::setFieldText(pcl::icf::findField(trackerFields(), "refine_max_points"), t, "321");
  EXPECT_EQ(t.tuning().refinement.max_points, 321u);
}

/** The message of what \a f throws, "" when it does not throw std::invalid_argument. */
template <typename F>
std::string refusal(F f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(FieldRegistry, RefusesWrongKindsRangesAndNamesNamingTheField) {
  LocalizerParams p;
  const auto& fields = localizerFields();
  const auto& keep = pcl::icf::findField(fields, "keep");
  const auto& gate = pcl::icf::findField(fields, "far_point_gate");
  const auto& confidence = pcl::icf::findField(fields, "min_confidence");
  const auto& strategy = pcl::icf::findField(fields, "strategy");
  EXPECT_EQ(refusal([&] { pcl::icf::setFieldNumber(keep, p, 2.5); }).rfind("keep: 2.5", 0), 0u);
  EXPECT_NE(refusal([&] { pcl::icf::setFieldNumber(keep, p, 0.0); }).find("outside"),
            std::string::npos);
  EXPECT_NE(refusal([&] { pcl::icf::setFieldNumber(gate, p, 2.0); }).find("not 0 or 1"),
            std::string::npos);
  EXPECT_NE(refusal([&] { pcl::icf::setFieldNumber(confidence, p, 1.5); }).find("outside"),
            std::string::npos);
  EXPECT_NE(refusal([&] { pcl::icf::setFieldText(confidence, p, "0.5x"); }).find("not a number"),
            std::string::npos);
  EXPECT_NE(refusal([&] { pcl::icf::setFieldText(confidence, p, "nan"); }).find("not a number"),
            std::string::npos);
  EXPECT_NE(refusal([&] { pcl::icf::setFieldText(strategy, p, "slow"); }).find("fast, thesis"),
            std::string::npos);
  EXPECT_NE(refusal([&] { pcl::icf::setFieldNumber(strategy, p, 1.0); }).find("names"),
            std::string::npos);
  const std::string unknown = refusal([&] { pcl::icf::findField(fields, "kep"); });
  EXPECT_NE(unknown.find("unknown field 'kep'"), std::string::npos);
  EXPECT_NE(unknown.find("keep"), std::string::npos);
  // Nothing refused was written.
  EXPECT_EQ(texts(fields, p), texts(fields, LocalizerParams{}));
}

// The judging's fields set in code, past the registry: validate() names the field.
TEST(FieldRegistry, ValidateNamesTheJudgingsFields) {
  LocalizerParams few;
  few.tuning().hypotheses.final_points = 9;
  EXPECT_NE(refusal([&] { few.validate(); }).find("final_points"), std::string::npos);
  LocalizerParams voters;
  voters.tuning().hypotheses.max_voting_points = 99;
  EXPECT_NE(refusal([&] { voters.validate(); }).find("max_voting_points"), std::string::npos);
  voters.tuning().hypotheses.max_voting_points = 0;  // no limit
  EXPECT_NO_THROW(voters.validate());
  LocalizerParams share;
  share.tuning().promising_share = 1.5;
  EXPECT_NE(refusal([&] { share.validate(); }).find("promising_share"), std::string::npos);
  share.tuning().promising_share = 0.0;  // every judged pose is worth its turns
  EXPECT_NO_THROW(share.validate());
}

}  // namespace
