/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "bench_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numeric>
#include <sstream>

namespace pcl_icf_tools {
namespace bench {

namespace fs = std::filesystem;

namespace {

void meanStd(const std::vector<double>& v, double& mean, double& sd) {
  mean = sd = 0.0;
  if (v.empty())
    return;
  mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  double ss = 0.0;
  for (double x : v)
    ss += (x - mean) * (x - mean);
  // Sample standard deviation (n - 1), as R's sd() that drew the thesis's figures.
  sd = v.size() > 1 ? std::sqrt(ss / static_cast<double>(v.size() - 1)) : 0.0;
}

std::string csvEscape(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos)
    return s;
  std::string out = "\"";
  for (char ch : s)
    out += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return out + "\"";
}

/** "k/N (x%)", or "—" for no cases. */
std::string countAndRate(std::size_t k, std::size_t n) {
  if (n == 0)
    return "—";
  char cell[64];
  std::snprintf(cell, sizeof(cell), "%zu/%zu (%.0f%%)", k, n,
                100.0 * static_cast<double>(k) / static_cast<double>(n));
  return cell;
}

/** One method's line of formatTable; the error columns are "—" without present cases. */
std::string tableLine(const std::string& method, const Summary& s) {
  char errors[256] = "— | — | — | — | — | — | — | —";
  if (s.n)
    std::snprintf(errors, sizeof(errors), "%.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f",
                  s.t_mean, s.t_median, s.t_std, s.r_mean, s.r_median, s.r_std, s.adds_mean,
                  s.adds_median);
  char success[32] = "—";
  if (s.n)
    std::snprintf(success, sizeof(success), "%.0f%%", 100.0 * s.success);
  char line[512];
  std::snprintf(line, sizeof(line), "| %s | %zu | %s | %zu | %s | %s | %.0f |\n", method.c_str(),
                s.n, success, s.absent, countAndRate(s.false_poses, s.absent).c_str(), errors,
                s.time_median);
  return line;
}

/** The summary CSV's fields after group and method; a rate or error without cases to
 * measure it on is empty. */
std::string summaryFields(const Summary& s) {
  std::ostringstream f;
  f << s.n << ",";
  if (s.n)
    f << s.success;
  f << "," << s.absent << ",";
  if (s.absent)
    f << s.false_pose_rate;
  f << ",";
  if (s.n)
    f << s.t_mean << "," << s.t_median << "," << s.t_std << "," << s.r_mean << "," << s.r_median
      << "," << s.r_std << "," << s.adds_mean << "," << s.adds_median;
  else
    f << ",,,,,,,";
  f << "," << s.time_median;
  return f.str();
}

}  // namespace

double median(std::vector<double> v) {
  if (v.empty())
    return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

Summary summarize(const std::vector<const Row*>& rows) {
  Summary s;
  std::vector<double> t, r, a, ms;
  for (const Row* row : rows) {
    ms.push_back(row->ms);
    if (row->absent) {
      ++s.absent;
      s.false_poses += row->false_pose;
      continue;
    }
    ++s.n;
    t.push_back(row->t_mm);
    r.push_back(row->r_deg);
    a.push_back(row->adds_mm);
    s.success += row->success;
  }
  if (s.n)
    s.success /= static_cast<double>(s.n);
  if (s.absent)
    s.false_pose_rate = static_cast<double>(s.false_poses) / static_cast<double>(s.absent);
  meanStd(t, s.t_mean, s.t_std);
  meanStd(r, s.r_mean, s.r_std);
  double unused;
  meanStd(a, s.adds_mean, unused);
  s.t_median = median(t);
  s.r_median = median(r);
  s.adds_median = median(a);
  s.time_median = median(ms);
  return s;
}

void writeCasesCsv(const fs::path& file, const std::vector<Row>& rows) {
  std::ofstream csv(file);
  csv << "case,group,method,points,t_err_mm,r_err_deg,r_err_nosym_deg,adds_mm,time_ms,"
         "success,converged,absent,false_pose,detail,pose_row_major,confidence,verification,"
         "success_among_alternatives,strict_success\n";
  csv.precision(6);
  for (const Row& r : rows) {
    csv << csvEscape(r.case_name) << "," << csvEscape(r.group) << "," << r.method << "," << r.points
        << ",";
    // A target-absent case has no errors: empty fields.
    if (r.absent)
      csv << ",,,,";
    else
      csv << r.t_mm << "," << r.r_deg << "," << r.r_nosym_deg << "," << r.adds_mm << ",";
    csv << r.ms << "," << r.success << "," << r.converged << "," << r.absent << "," << r.false_pose
        << "," << csvEscape(r.detail) << ",";
    // The estimated pose (model -> scene), the top 3 rows; full precision to recompute.
    csv.precision(9);
    for (int i = 0; i < 12; ++i)
      csv << (i ? " " : "") << r.object_pose(i / 4, i % 4);
    csv.precision(6);
    csv << ",";
    if (std::isfinite(r.confidence))
      csv << r.confidence;
    csv << "," << csvEscape(r.verification) << "," << r.success_among_alternatives << ","
        << r.strict_success << "\n";
  }
}

void writeSummaryCsv(const fs::path& file, const std::vector<std::string>& groups,
                     const std::vector<std::string>& methods, const RowSelector& rowsOf) {
  std::ofstream csv(file);
  csv << "group,method,cases,success_rate,absent_cases,false_pose_rate,t_mean_mm,t_median_mm,"
         "t_std_mm,r_mean_deg,r_median_deg,r_std_deg,adds_mean_mm,adds_median_mm,"
         "time_median_ms\n";
  std::vector<std::string> all_groups = {""};
  all_groups.insert(all_groups.end(), groups.begin(), groups.end());
  for (const auto& g : all_groups)
    for (const auto& m : methods) {
      const auto selected = rowsOf(g, m);
      if (selected.empty())
        continue;
      const Summary s = summarize(selected);
      csv << csvEscape(g.empty() ? "ALL" : g) << "," << m << "," << summaryFields(s) << "\n";
    }
}

std::string formatTable(const std::vector<std::string>& methods,
                        const std::function<std::vector<const Row*>(const std::string&)>& rowsOf) {
  std::ostringstream md;
  md << "| method | cases | success (1 cm, ADD-S 10%) | absent | false poses | t mean (mm) | t "
        "median "
        "| t std | r mean (°) | r median | r std | ADD-S mean (mm) | ADD-S median | median time "
        "(ms) |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& m : methods) {
    const auto rows = rowsOf(m);
    if (!rows.empty())
      md << tableLine(m, summarize(rows));
  }
  return md.str();
}

void writePlots(const fs::path& data_dir, const fs::path& dir, const std::string& name,
                const std::vector<std::string>& groups, const std::vector<std::string>& methods,
                const RowSelector& rowsOf) {
  fs::create_directories(dir);
  fs::create_directories(data_dir);
  const fs::path data = data_dir / (name + "_plot.dat");
  {
    std::ofstream out(data);
    // Columns: group, then per method t_mean t_std r_mean r_std.
    out << "# group";
    for (const auto& m : methods)
      out << " " << m << "_tmean " << m << "_tstd " << m << "_rmean " << m << "_rstd";
    out << "\n";
    for (const auto& g : groups) {
      out << "\"" << g << "\"";
      for (const auto& m : methods) {
        const Summary s = summarize(rowsOf(g, m));
        // Floors keep zero bars drawable on the log axis.
        out << " " << std::max(s.t_mean, 0.01) << " " << std::max(s.t_std, 0.01) << " "
            << std::max(s.r_mean, 0.01) << " " << std::max(s.r_std, 0.01);
      }
      out << "\n";
    }
  }
  const fs::path script = data_dir / (name + "_plot.gp");
  {
    std::ofstream gp(script);
    gp << "set terminal pngcairo noenhanced size 1400,1000 font 'sans,11'\n"
       << "set style data histogram\nset style histogram clustered gap 1\n"
       << "set style fill solid 0.85 border -1\nset boxwidth 0.9\nset logscale y\n"
       << "set grid ytics\nset key outside right top vertical\nset xtics nomirror\n"
       << "set datafile missing '?'\n"
       << "set xrange [-0.6:" << static_cast<double>(groups.size()) - 0.4 << "]\n";
    const char* what[2] = {"mean", "std"};
    const char* title[2] = {"Mean error", "Standard deviation of the error"};
    // A standard deviation needs two cases in some group.
    bool spread = false;
    for (const auto& g : groups)
      for (const auto& m : methods)
        spread = spread || rowsOf(g, m).size() >= 2;
    for (int k = 0; k < (spread ? 2 : 1); ++k) {
      gp << "set output '" << (dir / (name + "_" + what[k] + ".png")).string() << "'\n"
         << "set multiplot layout 2,1 title '" << title[k] << " per group and method (" << name
         << "; log scale)'\n";
      for (int panel = 0; panel < 2; ++panel) {
        gp << "set ylabel '"
           << (panel == 0 ? "(a) translation error (mm)" : "(b) rotation error (deg)")
           << "'\nplot ";
        for (std::size_t m = 0; m < methods.size(); ++m) {
          const std::size_t col =
              2 + 4 * m + 2 * static_cast<std::size_t>(panel) + static_cast<std::size_t>(k);
          gp << (m ? ", " : "") << "'" << data.string() << "' using " << col
             << (m == 0 ? ":xtic(1)" : "") << " title '" << methods[m] << "'";
        }
        gp << "\n";
      }
      gp << "unset multiplot\n";
    }
  }
  const std::string command = "gnuplot '" + script.string() + "' 2>&1";
  if (std::system(command.c_str()) != 0)
    std::fprintf(stderr,
                 "pcl_icf_bench: gnuplot failed (is gnuplot-nox installed?); the "
                 "data and script are in %s\n",
                 data_dir.string().c_str());
}

}  // namespace bench
}  // namespace pcl_icf_tools
