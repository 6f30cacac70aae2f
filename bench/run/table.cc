#include "bench/run/table.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "bench/run/stats.h"

namespace calibench {
namespace {

std::vector<RunRow> ReferenceRows(const ScenarioConfig& s, const std::vector<RunRow>& rows) {
  const std::string method = ReferenceMethod(s);
  std::vector<RunRow> out;
  for (const RunRow& r : rows) {
    if (r.scenario == s.name && r.method == method) out.push_back(r);
  }
  return out;
}

std::vector<double> Column(const std::vector<RunRow>& rows, double RunRow::*field) {
  std::vector<double> v;
  v.reserve(rows.size());
  for (const RunRow& r : rows) v.push_back(r.*field);
  return v;
}

std::string Num(double v, const char* fmt = "%.1f") {
  if (!std::isfinite(v)) return "–";
  char buf[64];
  std::snprintf(buf, sizeof(buf), fmt, v);
  return buf;
}

// "value" for one trial, "median [p2.5, p97.5]" for several.
std::string Cell(const std::vector<RunRow>& rows, double RunRow::*field, const char* fmt) {
  const std::vector<double> v = Column(rows, field);
  if (rows.size() == 1) return Num(v[0], fmt);
  return Num(Median(v), fmt) + " [" + Num(Quantile(v, 0.025), fmt) + ", " +
         Num(Quantile(v, 0.975), fmt) + "]";
}

struct Figure {
  const char* name;
  double RunRow::*field;
  double reference;
};

std::vector<Figure> Figures(const Reference& ref) {
  std::vector<Figure> f = {
      {"fku", &RunRow::fku_px, ref.fku_px},   {"fkv", &RunRow::fkv_px, ref.fkv_px},
      {"phi", &RunRow::phi_deg, ref.phi_deg}, {"u0", &RunRow::u0_px, ref.u0_px},
      {"v0", &RunRow::v0_px, ref.v0_px},      {"xc_x", &RunRow::xc_x_m, ref.x_c[0]},
      {"xc_y", &RunRow::xc_y_m, ref.x_c[1]},  {"xc_z", &RunRow::xc_z_m, ref.x_c[2]}};
  std::vector<Figure> present;
  for (const Figure& x : f) {
    if (std::isfinite(x.reference)) present.push_back(x);
  }
  return present;
}

std::string ReferenceText(const Reference& ref) {
  std::ostringstream s;
  if (std::isfinite(ref.theta_err_below)) s << "exact, ‖θ̃‖ < " << ref.theta_err_below;
  std::vector<std::string> parts;
  for (double v : {ref.fku_px, ref.fkv_px}) {
    if (std::isfinite(v)) parts.push_back(Num(v));
  }
  if (std::isfinite(ref.phi_deg)) parts.push_back(Num(ref.phi_deg) + "°");
  for (double v : {ref.u0_px, ref.v0_px}) {
    if (std::isfinite(v)) parts.push_back(Num(v));
  }
  for (size_t i = 0; i < parts.size(); ++i) s << (i ? ", " : "") << parts[i];
  if (ref.x_c.allFinite()) {
    s << "; x_C=[" << Num(ref.x_c[0], "%.4f") << ", " << Num(ref.x_c[1], "%.4f") << ", "
      << Num(ref.x_c[2], "%.4f") << "]";
  }
  return s.str();
}

}  // namespace

std::string ReferenceMethod(const ScenarioConfig& s) {
  if (!s.reference.method.empty()) return s.reference.method;
  const std::vector<const MethodInstance*> enabled = s.EnabledMethods();
  return enabled.empty() ? "" : enabled.front()->name;
}

ReferenceCheck CheckAgainstReference(const ScenarioConfig& scenario,
                                     const std::vector<RunRow>& all_rows) {
  ReferenceCheck check;
  const std::vector<RunRow> rows = ReferenceRows(scenario, all_rows);
  const Reference& ref = scenario.reference;
  if (!ref.Any() || rows.empty()) return check;
  check.has_reference = true;
  if (std::isfinite(ref.theta_err_below)) {
    check.exact_expected = true;
    check.exact_met = Median(Column(rows, &RunRow::theta_err_norm)) < ref.theta_err_below;
  }
  for (const Figure& f : Figures(ref)) {
    const std::vector<double> v = Column(rows, f.field);
    ++check.figures;
    if (rows.size() > 1) {
      if (Quantile(v, 0.025) <= f.reference && f.reference <= Quantile(v, 0.975)) {
        ++check.inside_interval;
      }
      continue;
    }
    const double dev = std::abs(v[0] - f.reference) / std::abs(f.reference);
    if (!(dev <= check.worst_relative_deviation)) {  // NaN counts as the worst.
      check.worst_relative_deviation = dev;
      check.worst_field = f.name;
    }
  }
  return check;
}

std::string ThesisTable(const std::vector<ScenarioConfig>& scenarios,
                        const std::vector<RunRow>& all_rows) {
  std::ostringstream t;
  t << "| scenario | trials | status | f·ku | f·kv | φ (°) | u0 | v0 | x_C | ‖θ̃‖ | t_conv (s) | "
       "reference | vs reference |\n";
  t << "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ScenarioConfig& s : scenarios) {
    const std::vector<RunRow> rows = ReferenceRows(s, all_rows);
    if (rows.empty()) continue;
    int ok = 0;
    for (const RunRow& r : rows) ok += r.status == "ok";
    const std::string status = ok == static_cast<int>(rows.size())
                                   ? "ok"
                                   : std::to_string(ok) + "/" + std::to_string(rows.size()) + " ok";
    const std::string xc = rows.size() == 1 ? "[" + Num(rows[0].xc_x_m, "%.4f") + ", " +
                                                  Num(rows[0].xc_y_m, "%.4f") + ", " +
                                                  Num(rows[0].xc_z_m, "%.4f") + "]"
                                            : "x " + Cell(rows, &RunRow::xc_x_m, "%.3f");
    const ReferenceCheck check = CheckAgainstReference(s, all_rows);
    std::string verdict;
    if (check.exact_expected) verdict = check.exact_met ? "exact ✓" : "not exact ✗";
    if (check.figures > 0) {
      if (!verdict.empty()) verdict += "; ";
      if (rows.size() > 1) {
        verdict += std::to_string(check.inside_interval) + "/" + std::to_string(check.figures) +
                   " inside our 95% interval";
      } else {
        verdict += "worst " + Num(100 * check.worst_relative_deviation, "%.2f") + "% (" +
                   check.worst_field + ")";
      }
    }
    t << "| " << s.name << " | " << rows.size() << " | " << status << " | "
      << Cell(rows, &RunRow::fku_px, "%.1f") << " | " << Cell(rows, &RunRow::fkv_px, "%.1f")
      << " | " << Cell(rows, &RunRow::phi_deg, "%.1f") << " | "
      << Cell(rows, &RunRow::u0_px, "%.1f") << " | " << Cell(rows, &RunRow::v0_px, "%.1f") << " | "
      << xc << " | " << Cell(rows, &RunRow::theta_err_norm, "%.2e") << " | "
      << Cell(rows, &RunRow::converge_time_s, "%.1f") << " | " << ReferenceText(s.reference)
      << " | " << verdict << " |\n";
  }
  return t.str();
}

}  // namespace calibench
