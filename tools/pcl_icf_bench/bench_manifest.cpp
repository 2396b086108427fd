/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "bench_manifest.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace pcl_icf_tools {
namespace bench {

namespace fs = std::filesystem;
namespace t = pcl::icf::synthetic;

namespace {

std::vector<double> parseNumbers(const std::string& text, const std::string& where) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(v))
      throw BadInput(where + ": '" + item + "' is not a finite number");
    values.push_back(v);
  }
  return values;
}

/** truth=: 16 (or 12) row-major numbers of a rigid transform. */
Eigen::Isometry3d parseTruth(const std::string& value, const std::string& where) {
  const auto v = parseNumbers(value, where);
  if (v.size() != 16 && v.size() != 12)
    throw BadInput(where + ": truth needs 16 (or 12) row-major numbers, or none");
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (std::size_t i = 0; i < v.size(); ++i)
    m(static_cast<int>(i / 4), static_cast<int>(i % 4)) = v[i];
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-4 || r.determinant() < 0.0)
    throw BadInput(where + ": truth's rotation is not a rotation");
  Eigen::Isometry3d pose;
  pose.matrix() = m;
  return pose;
}

}  // namespace

t::Symmetry parseSymmetry(const std::string& spec, const std::string& where) {
  const std::string kind = spec.substr(0, spec.find(':'));
  const std::string args =
      spec.find(':') == std::string::npos ? "" : spec.substr(spec.find(':') + 1);
  if (kind == "none" && args.empty())
    return t::Symmetry::none();
  if (kind == "box") {
    const auto s = parseNumbers(args, where);
    if (s.size() != 3)
      throw BadInput(where + ": symmetry=box:SX,SY,SZ needs three sizes");
    return t::Symmetry::box(s[0], s[1], s[2]);
  }
  if (kind == "prism") {
    const auto n = parseNumbers(args, where);
    if (n.size() != 1 || n[0] < 1 || n[0] != std::floor(n[0]))
      throw BadInput(where + ": symmetry=prism:N needs a whole N >= 1");
    return t::Symmetry::prism(static_cast<int>(n[0]));
  }
  if (kind == "cylinder" && (args.empty() || args == "noflip"))
    return t::Symmetry::cylinder(args.empty());
  if (kind == "halfturn" && (args == "x" || args == "y" || args == "z")) {
    // The identity and a half turn about one axis (YCB-Video's foam brick about z).
    t::Symmetry s;
    s.kind = t::Symmetry::Kind::Discrete;
    const int axis = args[0] - 'x';
    s.group = {Eigen::Matrix3d::Identity(),
               Eigen::AngleAxisd(M_PI, Eigen::Vector3d::Unit(axis)).toRotationMatrix()};
    return s;
  }
  throw BadInput(where + ": unknown symmetry '" + spec +
                 "' (none, box:SX,SY,SZ, prism:N, cylinder, cylinder:noflip, halfturn:x|y|z)");
}

std::vector<CaseSpec> readManifest(const fs::path& path) {
  std::ifstream in(path);
  if (!in)
    throw BadInput(path.string() + ": cannot read the manifest");
  const fs::path base = path.parent_path();
  std::vector<CaseSpec> cases;
  std::set<std::string> names;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string where = path.string() + ":" + std::to_string(number);
    const auto hash = line.find('#');
    if (hash != std::string::npos)
      line.erase(hash);
    std::stringstream tokens(line);
    std::string token;
    CaseSpec c;
    c.source = where;
    std::map<std::string, std::string> fields;
    while (tokens >> token) {
      const auto eq = token.find('=');
      if (eq == std::string::npos || eq == 0)
        throw BadInput(where + ": '" + token + "' is not key=value");
      const std::string key = token.substr(0, eq);
      if (!fields.emplace(key, token.substr(eq + 1)).second)
        throw BadInput(where + ": " + key + " given twice");
    }
    if (fields.empty())
      continue;
    for (const char* required : {"name", "scene", "model", "truth"})
      if (!fields.count(required))
        throw BadInput(where + ": missing " + required + "=");
    for (const auto& [key, value] : fields) {
      if (key == "name")
        c.name = value;
      else if (key == "group")
        c.group = value;
      else if (key == "scene")
        c.scene = base / value;
      else if (key == "model")
        c.model = base / value;
      else if (key == "units") {
        if (value == "m")
          c.scale = 1.0;
        else if (value == "mm")
          c.scale = 1e-3;
        else
          throw BadInput(where + ": units must be m or mm, not " + value);
      } else if (key == "truth") {
        c.absent = value == "none";
        if (!c.absent)
          c.truth = parseTruth(value, where);
      } else if (key == "symmetry") {
        parseSymmetry(value, where);
        c.symmetry_spec = value;
      } else if (key == "center") {
        const auto v = parseNumbers(value, where);
        if (v.size() != 3)
          throw BadInput(where + ": center needs three numbers");
        c.reference.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
        c.center_set = true;
      } else if (key == "axes") {
        const auto v = parseNumbers(value, where);
        if (v.size() != 9)
          throw BadInput(where + ": axes needs nine row-major numbers");
        Eigen::Matrix3d r;
        for (int i = 0; i < 9; ++i)
          r(i / 3, i % 3) = v[static_cast<std::size_t>(i)];
        if ((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-4 ||
            r.determinant() < 0.0)
          throw BadInput(where + ": axes is not a rotation");
        c.reference.linear() = r;
      } else if (key == "camera") {
        const auto v = parseNumbers(value, where);
        if (v.size() != 3)
          throw BadInput(where + ": camera needs three numbers");
        c.camera = Eigen::Vector3d(v[0], v[1], v[2]).cast<float>();
        c.camera_set = true;
      } else if (key == "cluster") {
        c.cluster = value;
        if (value.rfind("indices:", 0) == 0)
          c.indices = base / value.substr(8);
        else if (value.rfind("crop:", 0) == 0) {
          const auto v = parseNumbers(value.substr(5), where);
          if (v.size() != 1 || v[0] < 0.0)
            throw BadInput(where + ": cluster=crop:MARGIN needs one margin >= 0 (metres)");
          c.crop_margin = v[0];
        } else if (value != "all")
          throw BadInput(where + ": cluster must be all, indices:FILE or crop:MARGIN");
      } else
        throw BadInput(where + ": unknown key " + key);
    }
    if (c.absent && c.cluster.rfind("crop:", 0) == 0)
      throw BadInput(where + ": cluster=crop needs the model's pose: not with truth=none");
    if (!names.insert(c.name).second)
      throw BadInput(where + ": case name " + c.name + " repeats");
    if (c.group.empty())
      c.group = c.model.stem().string();
    cases.push_back(c);
  }
  return cases;
}

}  // namespace bench
}  // namespace pcl_icf_tools
