#include "bench/report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include "bench/classification_tables.h"
#include "synth/generate.h"
#include "synth/mesh.h"
#include "bench/stereo_tables.h"

namespace grapebench {

namespace {

const char* kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e",
                          "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"};
const char* colour(std::size_t i) { return kPalette[i % 10]; }

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<')
      o += "&lt;";
    else if (c == '>')
      o += "&gt;";
    else if (c == '&')
      o += "&amp;";
    else if (c == '"')
      o += "&quot;";
    else
      o += c;
  }
  return o;
}

// Plain notation ("3291", "0.0123", "-12.5") with at least `prec` significant digits;
// scientific only outside [1e-4, 1e9).
std::string fmt(double v, int prec = 3) {
  if (!std::isfinite(v)) return "-";
  char b[48];
  const double a = std::abs(v);
  if (a == 0) return "0";
  if (a < 1e-4 || a >= 1e9) {
    std::snprintf(b, sizeof b, "%.*g", prec, v);
    return b;
  }
  const int decimals = std::max(0, prec - 1 - static_cast<int>(std::floor(std::log10(a))));
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}

// An axis label: plain notation without trailing zeros ("2", "0.25", "2000").
std::string tick_label(double v) {
  std::string t = fmt(v, 4);
  if (t.find('.') != std::string::npos && t.find('e') == std::string::npos) {
    while (t.back() == '0') t.pop_back();
    if (t.back() == '.') t.pop_back();
  }
  return t;
}

// "1167 [782, 1526]": a figure with its 95 % interval.
std::string with_interval(double v, const Interval& i, int prec = 3) {
  if (!std::isfinite(i.lo)) return fmt(v, prec);
  return fmt(v, prec) + " <small>[" + fmt(i.lo, prec) + ", " + fmt(i.hi, prec) + "]</small>";
}

// "Nice" tick values covering [lo, hi].
std::vector<double> ticks(double lo, double hi) {
  const double span = hi - lo;
  const double raw = span / 5;
  const double mag = std::pow(10, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (raw <= m * mag) {
      step = m * mag;
      break;
    }
  }
  std::vector<double> t;
  for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * span; v += step)
    t.push_back(std::abs(v) < 1e-12 * step ? 0 : v);
  return t;
}

struct Series {
  std::string name;
  std::vector<double> x, y, ylo, yhi;  // ylo/yhi: optional error bars
  bool line = false;
};

// A scatter or line plot with axes, ticks, a legend (top left, or bottom right where
// the curves rise through the top left, as ROC curves do) and an optional y = x line.
enum class Legend { TopLeft, BottomRight };
std::string plot(const std::string& title, const std::string& xlabel, const std::string& ylabel,
                 const std::vector<Series>& series, bool identity, Legend legend = Legend::TopLeft) {
  const double W = 460, H = 340, L = 64, R = 16, T = 30, B = 46;
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& s : series) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x0 = std::min(x0, s.x[i]);
      x1 = std::max(x1, s.x[i]);
      y0 = std::min(y0, s.ylo.empty() ? s.y[i] : s.ylo[i]);
      y1 = std::max(y1, s.yhi.empty() ? s.y[i] : s.yhi[i]);
    }
  }
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" viewBox=\"0 0 " << W
    << " " << H
    << "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o << "<text x=\"" << W / 2 << "\" y=\"18\" text-anchor=\"middle\" font-size=\"13\">" << esc(title) << "</text>\n";
  if (!std::isfinite(x0)) {
    o << "<text x=\"" << W / 2 << "\" y=\"" << H / 2 << "\" text-anchor=\"middle\">no data</text></svg>\n";
    return o.str();
  }
  if (identity) {
    x0 = y0 = std::min(x0, y0);
    x1 = y1 = std::max(x1, y1);
  }
  const auto pad = [](double& a, double& b) {
    const double d = b - a > 0 ? b - a : std::max(std::abs(a), 1.0);
    a -= 0.05 * d;
    b += 0.05 * d;
  };
  pad(x0, x1);
  pad(y0, y1);
  const auto px = [&](double x) { return L + (x - x0) / (x1 - x0) * (W - L - R); };
  const auto py = [&](double y) { return H - B - (y - y0) / (y1 - y0) * (H - T - B); };
  o << "<rect x=\"" << L << "\" y=\"" << T << "\" width=\"" << W - L - R << "\" height=\"" << H - T - B
    << "\" fill=\"none\" stroke=\"#444\"/>\n";
  for (double t : ticks(x0, x1)) {
    o << "<line x1=\"" << px(t) << "\" x2=\"" << px(t) << "\" y1=\"" << T << "\" y2=\"" << H - B
      << "\" stroke=\"#eee\"/><text x=\"" << px(t) << "\" y=\"" << H - B + 14 << "\" text-anchor=\"middle\">"
      << tick_label(t) << "</text>\n";
  }
  for (double t : ticks(y0, y1)) {
    o << "<line x1=\"" << L << "\" x2=\"" << W - R << "\" y1=\"" << py(t) << "\" y2=\"" << py(t)
      << "\" stroke=\"#eee\"/><text x=\"" << L - 4 << "\" y=\"" << py(t) + 4 << "\" text-anchor=\"end\">" << tick_label(t)
      << "</text>\n";
  }
  o << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 10 << "\" text-anchor=\"middle\">" << esc(xlabel)
    << "</text>\n";
  o << "<text transform=\"translate(14," << (T + H - B) / 2 << ") rotate(-90)\" text-anchor=\"middle\">" << esc(ylabel)
    << "</text>\n";
  if (identity) {
    o << "<line x1=\"" << px(x0) << "\" y1=\"" << py(x0) << "\" x2=\"" << px(x1) << "\" y2=\"" << py(x1)
      << "\" stroke=\"#888\" stroke-dasharray=\"4 3\"/>\n";
  }
  for (std::size_t k = 0; k < series.size(); ++k) {
    const auto& s = series[k];
    if (s.line && s.x.size() > 1) {
      o << "<polyline fill=\"none\" stroke=\"" << colour(k) << "\" stroke-width=\"1.5\" points=\"";
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (std::isfinite(s.y[i])) o << px(s.x[i]) << "," << py(s.y[i]) << " ";
      }
      o << "\"/>\n";
    }
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      if (!s.ylo.empty()) {
        o << "<line x1=\"" << px(s.x[i]) << "\" x2=\"" << px(s.x[i]) << "\" y1=\"" << py(s.ylo[i]) << "\" y2=\""
          << py(s.yhi[i]) << "\" stroke=\"" << colour(k) << "\"/>";
      }
      o << "<circle cx=\"" << px(s.x[i]) << "\" cy=\"" << py(s.y[i]) << "\" r=\"3\" fill=\"" << colour(k)
        << "\" fill-opacity=\"0.75\"/>";
    }
    o << "\n";
  }
  if (series.size() > 1 || (!series.empty() && !series[0].name.empty())) {
    const double n = static_cast<double>(series.size());
    for (std::size_t k = 0; k < series.size(); ++k) {
      const double y = legend == Legend::TopLeft ? T + 12 + 14 * static_cast<double>(k)
                                                 : H - B - 8 - 14 * (n - 1 - static_cast<double>(k));
      const double x = legend == Legend::TopLeft ? L + 10 : W - R - 150;
      o << "<circle cx=\"" << x << "\" cy=\"" << y - 4 << "\" r=\"4\" fill=\"" << colour(k) << "\"/><text x=\""
        << x + 8 << "\" y=\"" << y << "\">" << esc(series[k].name) << "</text>\n";
    }
  }
  o << "</svg>\n";
  return o.str();
}

// Horizontal bars (median) with p25-p75 whiskers, log-free, seconds.
std::string time_plot(const std::vector<std::string>& names, const std::vector<double>& med,
                      const std::vector<double>& lo, const std::vector<double>& hi) {
  const double W = 560, row = 22, L = 150, R = 80, T = 30;
  const double H = T + row * static_cast<double>(names.size()) + 36;
  double mx = 0;
  for (std::size_t i = 0; i < names.size(); ++i) mx = std::max(mx, std::isfinite(hi[i]) ? hi[i] : 0);
  if (mx <= 0) mx = 1;
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" viewBox=\"0 0 " << W
    << " " << H
    << "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << W / 2
    << "\" y=\"18\" text-anchor=\"middle\" font-size=\"13\">time per run (median, p25-p75)</text>\n";
  const auto px = [&](double v) { return L + v / mx * (W - L - R); };
  for (std::size_t i = 0; i < names.size(); ++i) {
    const double y = T + row * static_cast<double>(i);
    const double m = std::isfinite(med[i]) ? med[i] : 0;
    o << "<text x=\"" << L - 6 << "\" y=\"" << y + 14 << "\" text-anchor=\"end\">" << esc(names[i]) << "</text>"
      << "<rect x=\"" << L << "\" y=\"" << y + 4 << "\" width=\"" << px(m) - L << "\" height=\"" << row - 8
      << "\" fill=\"" << colour(i) << "\"/>";
    if (std::isfinite(lo[i]) && std::isfinite(hi[i])) {
      o << "<line x1=\"" << px(lo[i]) << "\" x2=\"" << px(hi[i]) << "\" y1=\"" << y + row / 2 << "\" y2=\""
        << y + row / 2 << "\" stroke=\"black\"/>";
    }
    o << "<text x=\"" << px(m) + 4 << "\" y=\"" << y + 14 << "\">" << fmt(m * 1e3, 3) << " ms</text>\n";
  }
  o << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 8 << "\" text-anchor=\"middle\">seconds (0 - " << fmt(mx, 3)
    << ")</text>\n</svg>\n";
  return o.str();
}

// Vertical bars grouped by `groups` (x), one colour per series, mean with +- sd
// whiskers; NaN means no data.
std::string grouped_bars(const std::string& title, const std::string& ylabel, const std::vector<std::string>& groups,
                         const std::vector<std::string>& series, const std::vector<std::vector<double>>& mean,
                         const std::vector<std::vector<double>>& sd) {
  const double W = 520, H = 300, L = 56, R = 120, T = 30, B = 40;
  double mx = 0;
  for (std::size_t i = 0; i < series.size(); ++i)
    for (std::size_t g = 0; g < groups.size(); ++g)
      if (std::isfinite(mean[i][g])) mx = std::max(mx, mean[i][g] + (std::isfinite(sd[i][g]) ? sd[i][g] : 0));
  if (mx <= 0) mx = 1;
  const double gw = (W - L - R) / std::max<double>(1, static_cast<double>(groups.size()));
  const double bw = 0.8 * gw / std::max<double>(1, static_cast<double>(series.size()));
  const auto py = [&](double v) { return T + (H - T - B) * (1 - v / mx); };
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" viewBox=\"0 0 " << W
    << " " << H
    << "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << W / 2 << "\" y=\"18\" text-anchor=\"middle\" font-size=\"13\">" << esc(title) << "</text>\n"
    << "<line x1=\"" << L << "\" x2=\"" << L << "\" y1=\"" << T << "\" y2=\"" << H - B << "\" stroke=\"black\"/>"
    << "<line x1=\"" << L << "\" x2=\"" << W - R << "\" y1=\"" << H - B << "\" y2=\"" << H - B
    << "\" stroke=\"black\"/>\n";
  for (int k = 0; k <= 4; ++k) {
    const double v = mx * k / 4;
    o << "<text x=\"" << L - 4 << "\" y=\"" << py(v) + 4 << "\" text-anchor=\"end\">" << fmt(v, 2) << "</text>";
  }
  o << "<text x=\"14\" y=\"" << (T + H - B) / 2 << "\" transform=\"rotate(-90 14 " << (T + H - B) / 2
    << ")\" text-anchor=\"middle\">" << esc(ylabel) << "</text>\n";
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const double x0 = L + gw * static_cast<double>(g) + 0.1 * gw;
    o << "<text x=\"" << L + gw * (static_cast<double>(g) + 0.5) << "\" y=\"" << H - B + 16
      << "\" text-anchor=\"middle\">" << esc(groups[g]) << "</text>";
    for (std::size_t i = 0; i < series.size(); ++i) {
      const double m = mean[i][g];
      if (!std::isfinite(m)) continue;
      const double x = x0 + bw * static_cast<double>(i);
      o << "<rect x=\"" << x << "\" y=\"" << py(m) << "\" width=\"" << bw * 0.9 << "\" height=\"" << py(0) - py(m)
        << "\" fill=\"" << colour(i) << "\"/>";
      if (std::isfinite(sd[i][g]) && sd[i][g] > 0) {
        const double xc = x + bw * 0.45;
        o << "<line x1=\"" << xc << "\" x2=\"" << xc << "\" y1=\"" << py(m + sd[i][g]) << "\" y2=\""
          << py(std::max(0.0, m - sd[i][g])) << "\" stroke=\"black\"/>";
      }
    }
    o << "\n";
  }
  for (std::size_t i = 0; i < series.size(); ++i) {
    const double y = T + 16 * static_cast<double>(i);
    o << "<rect x=\"" << W - R + 8 << "\" y=\"" << y << "\" width=\"10\" height=\"10\" fill=\"" << colour(i) << "\"/>"
      << "<text x=\"" << W - R + 22 << "\" y=\"" << y + 9 << "\">" << esc(series[i]) << "</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

std::string file_name(std::string s) {
  for (char& c : s) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  }
  return s;
}

// What every section of the report reads.
struct ReportContext {
  const SceneSet& set;
  const std::vector<CaseResult>& cases;
  const std::vector<ScoreRow>& scores;
  const std::vector<SizeErrorCell>& size_cells;
  std::vector<std::pair<std::string, std::string>> eq;  // (estimator, quantity) in scene order
};

// The page head and the run's description.
void header(const ReportContext& ctx, [[maybe_unused]] Report& rep, std::ostringstream& h) {
  [[maybe_unused]] const auto& [set, cases, scores, size_cells, eq] = ctx;
  h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>grapebench: " << esc(set.base.name)
    << "</title>\n<style>body{font-family:sans-serif;margin:24px;max-width:1500px}table{border-collapse:collapse;"
       "font-size:13px}td,th{border:1px solid #ccc;padding:3px 7px;text-align:right}th{background:#f3f3f3}"
       "td.l,th.l{text-align:left}.plots{display:flex;flex-wrap:wrap;gap:8px}</style>\n"
       // Script errors are collected here and shown at the page's end (and read by the browser test).
       "<script>window.reportErrors=[];window.addEventListener('error',function(e){"
       "window.reportErrors.push(String(e.message));});</script></head><body>\n";
  h << "<h1>grapebench run: " << esc(set.base.name) << "</h1>\n<p>Scene file <code>" << esc(set.base.path)
    << "</code>, " << cases.size() << " cases (" << set.conditions.size() << " condition(s) x "
    << (set.conditions.empty() ? 0 : bunch_jobs(set.conditions[0].scene).size())
    << " bunches). Errors are estimate - truth; "
    << "R2 is the squared correlation (the papers'), slope/intercept of the least-squares fit estimate = a truth + b. "
       "Volumes in cm3, lengths in mm.</p>\n";
}

// Scores table: each figure with its 95 % bootstrap interval (BCa, seeded).
void scores_section(const ReportContext& ctx, [[maybe_unused]] Report& rep, std::ostringstream& h) {
  [[maybe_unused]] const auto& [set, cases, scores, size_cells, eq] = ctx;
  if (scores.empty()) return;  // no scalar output (classification)
  h << "<h2>Scores</h2>\n<p>Brackets: 95 % bootstrap intervals (BCa, 2000 resamples of the cases, seeded from the "
       "scene). CCC: Lin's concordance of estimate and truth. Limits of agreement: Bland-Altman, mean difference "
       "+- 1.96 sd.</p>\n<table><tr><th class=l>condition</th><th class=l>estimator</th><th class=l>quantity</th>"
       "<th>ok</th><th>R2</th><th>RMSE</th><th>MAE</th><th>bias</th><th>MAPE %</th><th>CCC</th>"
       "<th>limits of agreement</th><th>slope</th><th>intercept</th><th>time median ms</th><th>peak heap MB</th></tr>\n";
  for (const auto& r : scores) {
    const Score& s = r.score;
    h << "<tr><td class=l>" << esc(set.conditions[static_cast<std::size_t>(r.condition)].label) << "</td><td class=l>"
      << esc(r.estimator) << "</td><td class=l>" << r.quantity << " (" << display_unit(r.quantity) << ")</td><td>"
      << s.succeeded << "/" << s.cases << "</td><td>" << with_interval(s.r2, r.intervals.r2) << "</td><td>"
      << with_interval(s.rmse, r.intervals.rmse) << "</td><td>" << fmt(s.mae) << "</td><td>"
      << with_interval(s.bias, r.intervals.bias) << "</td><td>" << with_interval(s.mape, r.intervals.mape)
      << "</td><td>" << fmt(r.concordance) << "</td><td>[" << fmt(r.agreement.lower) << ", " << fmt(r.agreement.upper)
      << "]</td><td>" << fmt(s.slope) << "</td><td>" << fmt(s.intercept) << "</td><td>" << fmt(s.time_median * 1e3)
      << "</td><td>" << fmt(r.peak_heap_mb_max) << "</td></tr>\n";
  }
  h << "</table>\n";
}

// Paired comparisons: which estimator is closer to the truth on the same bunches.
void comparisons_section(const ReportContext& ctx, [[maybe_unused]] Report& rep, std::ostringstream& h) {
  [[maybe_unused]] const auto& [set, cases, scores, size_cells, eq] = ctx;
  const std::vector<ComparisonRow> rows = paired_comparisons(set, scores);
  if (rows.empty()) return;
  h << "<h2>Paired comparisons</h2>\n<p>For two estimators on the measurements both made: d = |error of A| - "
       "|error of B| (negative: A is closer to the truth), its mean with a 95 % bootstrap interval, and the "
       "two-sided Wilcoxon signed-rank p. A verdict is given only where the interval excludes 0.</p>\n"
       "<table><tr><th class=l>condition</th><th class=l>quantity</th><th class=l>A</th><th class=l>B</th>"
       "<th>cases</th><th>mean d</th><th>95 % interval</th><th>Wilcoxon p</th><th class=l>verdict</th></tr>\n";
  for (const ComparisonRow& c : rows) {
    const PairedComparison& p = c.comparison;
    const bool a_better = p.interval.hi < 0, b_better = p.interval.lo > 0;
    h << "<tr><td class=l>" << esc(set.conditions[static_cast<std::size_t>(c.condition)].label) << "</td><td class=l>"
      << c.quantity << " (" << display_unit(c.quantity) << ")</td><td class=l>" << esc(c.a) << "</td><td class=l>"
      << esc(c.b) << "</td><td>" << p.cases << "</td><td>" << fmt(p.mean_difference) << "</td><td>["
      << fmt(p.interval.lo) << ", " << fmt(p.interval.hi) << "]</td><td>" << fmt(p.test.p, 2) << "</td><td class=l>"
      << (a_better ? esc(c.a) + " closer" : b_better ? esc(c.b) + " closer" : "not separated") << "</td></tr>\n";
  }
  h << "</table>\n";
}

// Box and strip per estimator: every estimator's errors of one quantity side by side.
std::string error_strips(const std::string& title, const std::string& xlabel, const std::vector<std::string>& names,
                         const std::vector<std::vector<double>>& errors) {
  const double row = 26, L = 150, R = 20, T = 30, B = 40, W = 620;
  const double H = T + B + row * static_cast<double>(names.size());
  double x0 = 0, x1 = 0;
  for (const auto& e : errors) {
    for (double v : e) {
      x0 = std::min(x0, v);
      x1 = std::max(x1, v);
    }
  }
  const double span = x1 > x0 ? x1 - x0 : 1;
  x0 -= 0.05 * span;
  x1 += 0.05 * span;
  const auto px = [&](double x) { return L + (x - x0) / (x1 - x0) * (W - L - R); };
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" viewBox=\"0 0 " << W
    << " " << H << "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << W / 2 << "\" y=\"18\" text-anchor=\"middle\" font-size=\"13\">" << esc(title) << "</text>\n";
  for (double t : ticks(x0, x1)) {
    o << "<line x1=\"" << px(t) << "\" x2=\"" << px(t) << "\" y1=\"" << T << "\" y2=\"" << H - B
      << "\" stroke=\"" << (t == 0 ? "#888" : "#eee") << "\"/><text x=\"" << px(t) << "\" y=\"" << H - B + 14
      << "\" text-anchor=\"middle\">" << tick_label(t) << "</text>\n";
  }
  o << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 8 << "\" text-anchor=\"middle\">" << esc(xlabel) << "</text>\n";
  for (std::size_t k = 0; k < names.size(); ++k) {
    const double y = T + row * (static_cast<double>(k) + 0.5);
    o << "<text x=\"" << L - 6 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">" << esc(names[k]) << "</text>\n";
    const auto& e = errors[k];
    if (e.empty()) continue;
    const double q1 = quantile(e, 0.25), q2 = quantile(e, 0.5), q3 = quantile(e, 0.75);
    o << "<line x1=\"" << px(*std::min_element(e.begin(), e.end())) << "\" x2=\"" << px(*std::max_element(e.begin(), e.end()))
      << "\" y1=\"" << y << "\" y2=\"" << y << "\" stroke=\"#999\"/><rect x=\"" << px(q1) << "\" y=\"" << y - 8
      << "\" width=\"" << std::max(px(q3) - px(q1), 1.0) << "\" height=\"16\" fill=\"" << colour(k)
      << "\" fill-opacity=\"0.25\" stroke=\"" << colour(k) << "\"/><line x1=\"" << px(q2) << "\" x2=\"" << px(q2)
      << "\" y1=\"" << y - 8 << "\" y2=\"" << y + 8 << "\" stroke=\"" << colour(k) << "\" stroke-width=\"2\"/>";
    for (double v : e) o << "<circle cx=\"" << px(v) << "\" cy=\"" << y << "\" r=\"2.5\" fill=\"" << colour(k) << "\"/>";
    o << "\n";
  }
  o << "</svg>\n";
  return o.str();
}

// The errors of every estimator of each quantity on one plot (all conditions pooled),
// and a Bland-Altman plot per estimator.
void error_distribution_section(const ReportContext& ctx, Report& rep, std::ostringstream& h) {
  [[maybe_unused]] const auto& [set, cases, scores, size_cells, eq] = ctx;
  std::vector<std::string> quantities;
  for (const auto& r : scores) {
    if (std::find(quantities.begin(), quantities.end(), r.quantity) == quantities.end()) quantities.push_back(r.quantity);
  }
  if (quantities.empty()) return;
  h << "<h2>Errors of all estimators</h2>\n<p>Estimate - truth per measurement, all conditions pooled; box: "
       "quartiles and median; line: range.</p>\n<div class=plots>\n";
  for (const std::string& q : quantities) {
    std::vector<std::string> names;
    std::vector<std::vector<double>> errors;
    for (const auto& r : scores) {
      if (r.quantity != q) continue;
      const auto at = std::find(names.begin(), names.end(), r.estimator);
      const std::size_t k = static_cast<std::size_t>(at - names.begin());
      if (at == names.end()) {
        names.push_back(r.estimator);
        errors.emplace_back();
      }
      for (std::size_t i = 0; i < r.estimates.size(); ++i) errors[k].push_back(r.estimates[i] - r.truths[i]);
    }
    const std::string svg = error_strips(q + ": error of each estimator", "estimate - truth (" + std::string(display_unit(q)) + ")", names, errors);
    rep.svgs["errors_" + file_name(q) + ".svg"] = svg;
    h << svg;
  }
  h << "</div>\n<h2>Bland-Altman</h2>\n<p>Difference estimate - truth against their mean; lines: the mean "
       "difference and its 95 % limits of agreement (one condition per colour, limits over all).</p>\n<div class=plots>\n";
  for (const auto& [est, q] : eq) {
    std::vector<Series> series;
    std::vector<double> est_all, truth_all;
    for (const auto& r : scores) {
      if (r.estimator != est || r.quantity != q) continue;
      Series s;
      s.name = set.conditions[static_cast<std::size_t>(r.condition)].label;
      for (std::size_t i = 0; i < r.estimates.size(); ++i) {
        s.x.push_back(0.5 * (r.estimates[i] + r.truths[i]));
        s.y.push_back(r.estimates[i] - r.truths[i]);
        est_all.push_back(r.estimates[i]);
        truth_all.push_back(r.truths[i]);
      }
      series.push_back(std::move(s));
    }
    const Agreement a = bland_altman(est_all, truth_all);
    if (!std::isfinite(a.mean_difference)) continue;
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0;
    for (const auto& s : series) {
      for (double x : s.x) {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
      }
    }
    const char* labels[] = {"lower limit", "mean difference", "upper limit"};
    int li = 0;
    for (const double level : {a.lower, a.mean_difference, a.upper}) {
      Series line;
      line.name = labels[li++];
      line.line = true;
      line.x = {x0, x1};
      line.y = {level, level};
      series.push_back(line);
    }
    const std::string unit = display_unit(q);
    const std::string svg = plot(est + ": " + q + ", mean " + fmt(a.mean_difference) + " [" + fmt(a.lower) + ", " +
                                     fmt(a.upper) + "] " + unit,
                                 "mean of estimate and truth (" + unit + ")", "estimate - truth (" + unit + ")", series, false);
    rep.svgs["bland_altman_" + file_name(est) + "_" + file_name(q) + ".svg"] = svg;
    h << svg;
  }
  h << "</div>\n";
}

// Segmentation, registration and cloud filters per condition.
void pipeline_section(const ReportContext& ctx, [[maybe_unused]] Report& rep, std::ostringstream& h) {
  [[maybe_unused]] const auto& [set, cases, scores, size_cells, eq] = ctx;
  h << "<h2>Pipeline: segmentation, registration, cloud filters</h2>\n<table><tr><th class=l>condition</th>"
       "<th class=l>segmentation</th><th>precision</th><th>recall</th><th class=l>registration</th><th>cases</th>"
       "<th>rotation error, mean of per-case max (deg)</th><th>worst (deg)</th><th>translation error, mean of max "
       "(mm)</th>"
       "<th>peduncle points kept</th><th>other bunch points kept</th><th>failed cases</th></tr>\n";
  const auto regs = registration_rows(set, cases);
  for (std::size_t c = 0; c < set.conditions.size(); ++c) {
    const RegistrationRow& r = regs[c];
    const auto& pl = set.conditions[c].scene.pipeline;
    h << "<tr><td class=l>" << esc(set.conditions[c].label) << "</td><td class=l>" << pl.segmentation_name();
    for (const auto& f : pl.view_filters) h << " + " << f.type;
    h << "</td><td>" << fmt(r.segmentation_precision) << "</td><td>" << fmt(r.segmentation_recall)
      << "</td><td class=l>" << registration_label(set.conditions[c].scene) << "</td><td>" << r.cases << "</td><td>"
      << fmt(r.rotation_max_deg_mean) << "</td><td>" << fmt(r.rotation_max_deg_worst) << "</td><td>"
      << fmt(r.translation_max_mm_mean) << "</td><td>";
    if (pl.cloud_filters.empty()) {
      h << "-</td><td>-";
    } else {
      h << fmt(r.peduncle_kept) << "</td><td>" << fmt(r.body_kept);
    }
    h << "</td><td>" << r.failed << "</td></tr>\n";
  }
  h << "</table>\n";
}

// Estimated vs true, per estimator and quantity, coloured by condition.
void scatter_section(const ReportContext& ctx, [[maybe_unused]] Report& rep, std::ostringstream& h) {
  [[maybe_unused]] const auto& [set, cases, scores, size_cells, eq] = ctx;
  if (eq.empty()) return;
  h << "<h2>Estimated vs true</h2>\n<div class=plots>\n";
  for (const auto& [est, q] : eq) {
    const double k = display_scale(q);
    std::vector<Series> series;
    for (std::size_t c = 0; c < set.conditions.size(); ++c) {
      Series s;
      s.name = set.conditions[c].label;
      for (const auto& cr : cases) {
        if (cr.condition != static_cast<int>(c)) continue;
        for (const auto& r : cr.rows) {
          if (r.estimator == est && r.quantity == q && r.ok) {
            s.x.push_back(r.truth * k);
            s.y.push_back(r.estimate * k);
          }
        }
      }
      series.push_back(std::move(s));
    }
    const std::string unit = display_unit(q);
    const std::string svg =
        plot(est + ": " + q, "true " + q + " (" + unit + ")", "estimated " + q + " (" + unit + ")", series, true);
    rep.svgs["scatter_" + file_name(est) + "_" + q + ".svg"] = svg;
    h << svg;
  }
  h << "</div>\n";
}

// Error vs each swept parameter (mean relative error with its spread over bunches).
void sweep_section(const ReportContext& ctx, [[maybe_unused]] Report& rep, std::ostringstream& h) {
  [[maybe_unused]] const auto& [set, cases, scores, size_cells, eq] = ctx;
  if (!set.base.sweep.empty()) {
    h << "<h2>Error vs swept parameters</h2>\n<div class=plots>\n";
    std::set<std::string> quantities;
    for (const auto& [e, q] : eq) quantities.insert(q);
    for (std::size_t a = 0; a < set.base.sweep.size(); ++a) {
      const auto& axis = set.base.sweep[a];
      for (const auto& q : quantities) {
        std::vector<Series> series;
        for (const auto& [est, qq] : eq) {
          if (qq != q) continue;
          Series s;
          s.name = est;
          s.line = true;
          for (double v : axis.values) {
            std::vector<double> rel;
            for (const auto& cr : cases) {
              if (set.conditions[static_cast<std::size_t>(cr.condition)].values[a] != v) continue;
              for (const auto& r : cr.rows) {
                if (r.estimator == est && r.quantity == q && r.ok) rel.push_back(100 * (r.estimate / r.truth - 1));
              }
            }
            double m = std::numeric_limits<double>::quiet_NaN(), sd = 0;
            if (!rel.empty()) {
              m = 0;
              for (double x : rel) m += x;
              m /= static_cast<double>(rel.size());
              for (double x : rel) sd += (x - m) * (x - m);
              sd = rel.size() > 1 ? std::sqrt(sd / static_cast<double>(rel.size() - 1)) : 0;
            }
            s.x.push_back(v);
            s.y.push_back(m);
            s.ylo.push_back(m - sd);
            s.yhi.push_back(m + sd);
          }
          series.push_back(std::move(s));
        }
        const std::string svg =
            plot(q + " error vs " + axis.key, axis.key, q + " error, % (mean +- sd over bunches)", series, false);
        rep.svgs["sweep_" + file_name(axis.key) + "_" + q + ".svg"] = svg;
        h << svg;
      }
    }
    h << "</div>\n";
  }
}

// Seed 003's ROI kinds, in table order.
const std::vector<std::string> kRoiKinds = {"auto_r", "auto_cm", "manual_r", "manual_cm"};

// The estimators of the pooled size-error cells, in order.
std::vector<std::string> size_error_estimators(const std::vector<SizeErrorCell>& cells) {
  std::vector<std::string> ests;
  for (const auto& c : cells) {
    if (c.condition == -1 && std::find(ests.begin(), ests.end(), c.estimator) == ests.end())
      ests.push_back(c.estimator);
  }
  return ests;
}

const SizeErrorCell* find_cell(const std::vector<SizeErrorCell>& cells, const std::string& e, const std::string& k,
                               int cond) {
  for (const auto& c : cells) {
    if (c.estimator == e && c.roi == k && c.condition == cond) return &c;
  }
  return nullptr;
}

// Seed 003's Table II: Err (Eq. 3) per estimator and ROI kind, all conditions pooled.
void size_error_table(const ReportContext& ctx, std::ostringstream& h) {
  [[maybe_unused]] const auto& [set, cases, scores, size_cells, eq] = ctx;
  const auto ests = size_error_estimators(size_cells);
  // Init-captures: clang 14 cannot capture structured bindings.
  const auto find = [&cells = size_cells](const std::string& e, const std::string& k, int cond) {
    return find_cell(cells, e, k, cond);
  };
  h << "<h2>Size error (seed 003 Table II)</h2>\n<p>Err = 0.5 |G1 - L| + 0.5 |G2 - W| (Eq. 3; measures and truths "
       "larger first), cm, mean +- sd over the fine-tuned ROIs (count); Filter keeps Err &lt; 10 cm. All conditions "
       "pooled; precision is the mean fraction of a tuned ROI on the bunch. Per condition: size_error.csv.</p>\n"
       "<table><tr><th class=l>estimator</th><th class=l></th>";
  for (const auto& k : kRoiKinds) h << "<th>" << k << "</th>";
  h << "</tr>\n";
  for (const auto& e : ests) {
    for (int f = 0; f < 3; ++f) {
      h << "<tr><td class=l>" << (f ? "" : esc(e)) << "</td><td class=l>"
        << (f == 0   ? "All"
            : f == 1 ? "Filter"
                     : "precision")
        << "</td>";
      for (const auto& k : kRoiKinds) {
        const SizeErrorCell* c = find(e, k, -1);
        if (!c || c->regions == 0) {
          h << "<td>-</td>";
        } else if (f < 2) {
          h << "<td>" << size_error_entry(*c, f == 1) << "</td>";
        } else {
          h << "<td>" << fmt(c->precision_mean, 3) << "</td>";
        }
      }
      h << "</tr>\n";
    }
  }
  h << "</table>\n";
}

// Figs. 8-9: Err of the paper's analysed variant (G_E on manual ROI_R, unfiltered) by
// the values of one swept axis, one series per value of another, pooling the rest.
void size_error_figures(const ReportContext& ctx, Report& rep, std::ostringstream& h) {
  [[maybe_unused]] const auto& [set, cases, scores, size_cells, eq] = ctx;
  const auto ests = size_error_estimators(size_cells);
  // Init-captures: clang 14 cannot capture structured bindings.
  const auto find = [&cells = size_cells](const std::string& e, const std::string& k, int cond) {
    return find_cell(cells, e, k, cond);
  };
  std::string est = ests.front(), roi = "manual_r";
  for (const auto& spec : set.base.estimators) {
    if (spec.type == "percentile_box_edges" && std::find(ests.begin(), ests.end(), spec.name) != ests.end())
      est = spec.name;
  }
  if (!find(est, roi, -1)) roi = find(est, "auto_r", -1) ? "auto_r" : kRoiKinds.front();
  const auto axis_value = [&s = set](std::size_t a, int cond) {
    const auto& ax = s.base.sweep[a];
    const double v = s.conditions[static_cast<std::size_t>(cond)].values[a];
    return ax.names.empty() ? fmt(v, 3) : ax.names[static_cast<std::size_t>(v)];
  };
  const std::size_t axes = set.base.sweep.size();
  if (axes > 0) {
    h << "<h2>Size error by condition (seed 003 Figs. 8-9)</h2>\n<p>" << esc(est) << " on " << esc(roi)
      << ", unfiltered, cm; bars: mean, whiskers: +- sd, pooled over the other axes.</p>\n<div class=plots>\n";
    for (std::size_t a = 0; a < axes; ++a) {
      for (std::size_t b = 0; b < axes; ++b) {
        if (b == a && axes > 1) continue;  // one axis alone: a single series
        const auto series_of = [&](int c) { return b == a ? std::string("all") : axis_value(b, c); };
        std::vector<std::string> groups, series;
        for (std::size_t c = 0; c < set.conditions.size(); ++c) {
          const std::string ga = axis_value(a, static_cast<int>(c)), sb = series_of(static_cast<int>(c));
          if (std::find(groups.begin(), groups.end(), ga) == groups.end()) groups.push_back(ga);
          if (std::find(series.begin(), series.end(), sb) == series.end()) series.push_back(sb);
        }
        std::vector<std::vector<double>> n(series.size(), std::vector<double>(groups.size(), 0)), sum = n, sq = n;
        for (std::size_t c = 0; c < set.conditions.size(); ++c) {
          const SizeErrorCell* cell = find(est, roi, static_cast<int>(c));
          if (!cell || cell->regions == 0) continue;
          const auto gi = static_cast<std::size_t>(
              std::find(groups.begin(), groups.end(), axis_value(a, static_cast<int>(c))) - groups.begin());
          const auto si = static_cast<std::size_t>(
              std::find(series.begin(), series.end(), series_of(static_cast<int>(c))) - series.begin());
          const double k = cell->regions, m = 100 * cell->mean, sd = 100 * cell->sd;
          n[si][gi] += k;
          sum[si][gi] += k * m;
          sq[si][gi] += (k - 1) * sd * sd + k * m * m;  // sum of squares, from the cell's mean and sd
        }
        std::vector<std::vector<double>> mean = n, sdv = n;
        for (std::size_t i = 0; i < series.size(); ++i) {
          for (std::size_t g = 0; g < groups.size(); ++g) {
            const double k = n[i][g];
            mean[i][g] = k > 0 ? sum[i][g] / k : std::nan("");
            sdv[i][g] =
                k > 1 ? std::sqrt(std::max(0.0, (sq[i][g] - k * mean[i][g] * mean[i][g]) / (k - 1))) : std::nan("");
          }
        }
        const std::string& ka = set.base.sweep[a].key;
        const std::string& kb = set.base.sweep[b].key;
        const std::string title = b == a ? "Err by " + ka : "Err by " + ka + " and " + kb;
        const std::string svg = grouped_bars(title, "Err, cm", groups, series, mean, sdv);
        rep.svgs["size_error_" + file_name(ka) + (b == a ? "" : "_by_" + file_name(kb)) + ".svg"] = svg;
        h << svg;
      }
    }
    h << "</div>\n";
  }
}

// Seed 003: Table II and Figs. 8-9 from the size-error cells.
void size_error_section(const ReportContext& ctx, Report& rep, std::ostringstream& h) {
  if (ctx.size_cells.empty()) return;
  size_error_table(ctx, h);
  size_error_figures(ctx, rep, h);
}

// Time per estimator (all conditions pooled).
void timing_section(const ReportContext& ctx, [[maybe_unused]] Report& rep, std::ostringstream& h) {
  [[maybe_unused]] const auto& [set, cases, scores, size_cells, eq] = ctx;
  std::vector<std::string> names;
  std::vector<double> med, lo, hi;
  // One time per run of each estimator: its rows of one case and one frame, ROI and
  // region share it (every protocol, whatever output kinds its rows rate).
  for (const EstimatorSpec& spec : set.base.estimators) {
    std::vector<double> t;
    for (const auto& cr : cases) {
      if (!cr.ok) continue;
      std::set<std::tuple<int, std::string, int>> runs;
      for (const auto& row : cr.rows) {
        if (row.estimator == spec.name && runs.emplace(row.frame, row.roi, row.region).second) t.push_back(row.seconds);
      }
    }
    names.push_back(spec.name);
    med.push_back(quantile(t, 0.5));
    lo.push_back(quantile(t, 0.25));
    hi.push_back(quantile(t, 0.75));
  }
  const std::string svg = time_plot(names, med, lo, hi);
  rep.svgs["time.svg"] = svg;
  h << "<h2>Time per estimator</h2>\n" << svg;
}

// Failures, if any, and the list of files.
void failures_section(const ReportContext& ctx, [[maybe_unused]] Report& rep, std::ostringstream& h) {
  [[maybe_unused]] const auto& [set, cases, scores, size_cells, eq] = ctx;
  std::ostringstream fails;
  for (const auto& cr : cases) {
    if (!cr.ok) {
      fails << "<tr><td>" << cr.condition << "</td><td>" << cr.bunch
            << "</td><td class=l>scan/registration</td><td class=l>" << esc(cr.error) << "</td></tr>\n";
      continue;
    }
    for (const auto& r : cr.rows) {
      if (!r.ok) {
        fails << "<tr><td>" << cr.condition << "</td><td>" << cr.bunch << "</td><td class=l>" << esc(r.estimator)
              << "</td><td class=l>" << esc(r.error) << "</td></tr>\n";
      }
    }
  }
  if (!fails.str().empty()) {
    h << "<h2>Failures</h2>\n<table><tr><th>condition</th><th>bunch</th><th class=l>step</th><th "
         "class=l>error</th></tr>\n"
      << fails.str() << "</table>\n";
  }
  h << "<p>Files: results.csv (one row per case, estimator and quantity), timings.csv, summary.json, timings.json, "
       "manifest.json (all parameters with defaults, seeds, version, build identity, libraries, machine), "
       "plots/*.svg.</p>\n";
}


// Seed 001's tables (stereo_pair runs): Table 2, Table 1 and Fig. 11 of Luo et al. 2016.
void stereo_section(const ReportContext& ctx, [[maybe_unused]] Report& rep, std::ostringstream& h) {
  std::vector<std::string> labels;
  for (const auto& c : ctx.set.conditions) labels.push_back(c.label.empty() ? "all" : c.label);
  const StereoTables t = stereo_tables(ctx.cases, labels);
  if (t.empty()) return;
  h << "<h2>Seed 001: cutting point, berries, depth</h2>\n<p>Table 2 of the paper: success of the cutting point "
       "(within the scene's cut_tolerance of a stalk pixel of the exact label image) per condition, with Wilson 95 % "
       "intervals (paper: 87 % over 300 images).</p>\n<table><tr><th class=l>estimator</th><th class=l>condition</th>"
       "<th>pairs</th><th>successes</th><th>rate %</th><th>95 % interval</th></tr>\n";
  for (const SuccessCell& s : t.success) {
    h << "<tr><td class=l>" << esc(s.estimator) << "</td><td class=l>" << esc(s.condition) << "</td><td>" << s.pairs
      << "</td><td>" << s.successes << "</td><td>" << fmt(100 * s.rate, 3) << "</td><td>" << fmt(100 * s.lo, 3) << "-"
      << fmt(100 * s.hi, 3) << "</td></tr>\n";
  }
  h << "</table>\n<p>Table 1 (berries visible: at least the scene's berry_visible_fraction of the disc unoccluded; "
       "found: matched by a detection, disc IoU >= 0.5) and Fig. 11 (mean |e_z|, |e_x| of the cutting point against "
       "the surface behind its pixel, over the pairs that answered) by station depth, 100 mm bins.</p>\n"
       "<table><tr><th class=l>estimator</th><th>depth mm</th><th>pairs</th><th>visible</th><th>found</th>"
       "<th>rate %</th><th>answered</th><th>|e_z| mm</th><th>|e_x| mm</th></tr>\n";
  std::map<std::string, std::array<Series, 2>> fig;
  for (const DepthCell& d : t.depth) {
    h << "<tr><td class=l>" << esc(d.estimator) << "</td><td>" << d.depth_mm << "</td><td>" << d.pairs << "</td><td>"
      << d.visible << "</td><td>" << d.found << "</td><td>" << (d.visible ? fmt(100.0 * d.found / d.visible, 3) : "-")
      << "</td><td>" << d.answered << "</td><td>" << (d.answered ? fmt(d.ez_mm, 3) : "-") << "</td><td>"
      << (d.answered ? fmt(d.ex_mm, 3) : "-") << "</td></tr>\n";
    if (!d.answered) continue;
    auto& [ez, ex] = fig[d.estimator];
    ez.name = ex.name = d.estimator;
    ez.line = ex.line = true;
    ez.x.push_back(d.depth_mm), ez.y.push_back(d.ez_mm);
    ex.x.push_back(d.depth_mm), ex.y.push_back(d.ex_mm);
  }
  h << "</table>\n";
  std::vector<Series> ez, ex;
  for (const auto& [name, pair] : fig) ez.push_back(pair[0]), ex.push_back(pair[1]);
  h << "<div class=plots>" << plot("Fig. 11a: mean |e_z| by depth", "depth (mm)", "|e_z| (mm)", ez, false)
    << plot("Fig. 11b: mean |e_x| by depth", "depth (mm)", "|e_x| (mm)", ex, false) << "</div>\n";
}

// Seed 004's figures (classification runs): per estimator the means over the row
// sections of the berry AUC, the operating point and the overall scores.
void classification_section(const ReportContext& ctx, [[maybe_unused]] Report& rep, std::ostringstream& h) {
  std::vector<std::string> labels;
  for (const auto& c : ctx.set.conditions) labels.push_back(c.label.empty() ? "all" : c.label);
  const std::vector<ClassificationCell> cells = classification_cells(ctx.cases, labels);
  if (cells.empty()) return;
  h << "<h2>Seed 004: per-point classification</h2>\n<p>Scored on the test part of each row section (the training "
       "part lies across the split gap). AUC: one class against the rest from the estimator's scores; tpr/fpr: the "
       "berry class's operating point of the argmax labels (paper, green set: 84.8 % at 11.6 % before the CRF, 91.9 % "
       "at 2.7 % after). Mean over the cases, with the smallest and largest.</p>\n<table><tr><th class=l>condition"
       "</th><th class=l>estimator</th><th class=l>quantity</th><th>cases</th><th>mean</th><th>min</th><th>max</th>"
       "</tr>\n";
  for (const ClassificationCell& c : cells) {
    h << "<tr><td class=l>" << esc(c.condition) << "</td><td class=l>" << esc(c.estimator) << "</td><td class=l>"
      << esc(c.quantity) << "</td><td>" << c.cases << "</td><td>" << fmt(c.mean, 4) << "</td><td>" << fmt(c.min, 4)
      << "</td><td>" << fmt(c.max, 4) << "</td></tr>\n";
  }
  h << "</table>\n<p>Confusion matrices summed over the cases (rows: true class; columns: predicted), with the "
       "accuracy and mIoU of the summed matrix (pooled over every test point; the table above averages per case).</p>"
       "\n<table><tr><th class=l>condition</th><th class=l>estimator</th><th class=l>true class</th>";
  const std::vector<PooledConfusion> first = pooled_confusion(ctx.cases, 0);
  for (const auto& name : first.empty() ? std::vector<std::string>{} : first.front().classes)
    h << "<th>as " << esc(name) << "</th>";
  h << "<th>pooled accuracy</th><th>pooled mIoU</th></tr>\n";
  for (std::size_t k = 0; k < labels.size(); ++k) {
    for (const PooledConfusion& p : pooled_confusion(ctx.cases, static_cast<int>(k))) {
      const std::size_t n = p.classes.size();
      for (std::size_t a = 0; a < n; ++a) {
        h << "<tr><td class=l>" << esc(labels[k]) << "</td><td class=l>" << esc(p.estimator) << "</td><td class=l>"
          << esc(p.classes[a]) << "</td>";
        for (std::size_t b = 0; b < n; ++b) h << "<td>" << p.counts[a * n + b] << "</td>";
        h << "<td>" << (a == 0 ? fmt(p.accuracy, 4) : "") << "</td><td>" << (a == 0 ? fmt(p.miou, 4) : "")
          << "</td></tr>\n";
      }
    }
  }
  h << "</table>\n<p>Figs. 4-7: the berry class's ROC curves, averaged over the cases at each false-positive rate; "
       "the second plot magnifies false-positive rates up to 0.2.</p>\n<div class=plots>";
  for (std::size_t k = 0; k < labels.size(); ++k) {
    std::vector<Series> full, zoom;
    for (const auto& [estimator, tpr] : mean_roc(ctx.cases, static_cast<int>(k), "berry")) {
      Series s{estimator, {}, {}, {}, {}, true}, z = s;
      for (std::size_t g = 0; g < tpr.size(); ++g) {
        const double fpr = static_cast<double>(g) / (tpr.size() - 1);
        s.x.push_back(fpr), s.y.push_back(tpr[g]);
        if (fpr <= 0.2 + 1e-9) z.x.push_back(fpr), z.y.push_back(tpr[g]);
      }
      full.push_back(std::move(s)), zoom.push_back(std::move(z));
    }
    if (full.empty()) continue;
    const std::string title = "berry ROC" + (labels.size() > 1 ? " (" + labels[k] + ")" : std::string());
    h << plot(title, "false-positive rate", "true-positive rate", full, false, Legend::BottomRight)
      << plot(title + ", FPR <= 0.2", "false-positive rate", "true-positive rate", zoom, false, Legend::BottomRight);
  }
  h << "</div>\n";
}

// The ground-truth mesh of the run's first bunch, coarse enough for a picture.
TriMesh first_bunch_mesh(const SceneSet& set) {
  const BunchJob job = bunch_jobs(set.conditions[0].scene).front();
  TriMesh mesh = bunch_mesh(generate_bunch(job.params, job.seed), MeshOptions{1, 8});
  TriMesh out;
  out.vertices = mesh.vertices;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (mesh.face_internal.empty() || !mesh.face_internal[f]) {
      out.faces.push_back(mesh.faces[f]);
      out.face_part.push_back(mesh.face_part[f]);
    }
  }
  return out;
}

// A side view (x right, z up, looking along +y) of the mesh, flat-shaded, back faces
// culled and the rest drawn far to near, beside the scan's points coloured by depth.
std::string side_view_svg(const TriMesh& mesh, const std::vector<std::array<float, 3>>& points) {
  double x0 = 1e9, x1 = -1e9, z0 = 1e9, z1 = -1e9;
  for (const Vec3& v : mesh.vertices) {
    x0 = std::min(x0, v.x() * 1e3), x1 = std::max(x1, v.x() * 1e3);
    z0 = std::min(z0, v.z() * 1e3), z1 = std::max(z1, v.z() * 1e3);
  }
  for (const auto& p : points) {
    x0 = std::min(x0, double(p[0])), x1 = std::max(x1, double(p[0]));
    z0 = std::min(z0, double(p[2])), z1 = std::max(z1, double(p[2]));
  }
  const double pad = 10, panel = 320, scale = (panel - 2 * pad) / std::max({x1 - x0, z1 - z0, 1.0});
  const auto px = [&](double x, double offset) { return offset + pad + (x - x0) * scale; };
  const auto py = [&](double z) { return panel - pad - (z - z0) * scale; };
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << 2 * panel << "\" height=\"" << panel + 24
    << "\" font-family=\"sans-serif\" font-size=\"12\"><rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << panel / 2 << "\" y=\"" << panel + 16 << "\" text-anchor=\"middle\">ground-truth mesh</text>"
    << "<text x=\"" << 1.5 * panel << "\" y=\"" << panel + 16 << "\" text-anchor=\"middle\">registered scan ("
    << points.size() << " points shown)</text>\n";
  struct Face {
    double depth;
    std::size_t index;
  };
  std::vector<Face> faces;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& t = mesh.faces[f];
    const Vec3 n = (mesh.vertices[static_cast<std::size_t>(t[1])] - mesh.vertices[static_cast<std::size_t>(t[0])])
                       .cross(mesh.vertices[static_cast<std::size_t>(t[2])] - mesh.vertices[static_cast<std::size_t>(t[0])]);
    if (n.y() >= 0) continue;  // faces away from a viewer at -y
    double d = 0;
    for (int k : t) d += mesh.vertices[static_cast<std::size_t>(k)].y();
    faces.push_back({-d, f});
  }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.depth < b.depth || (a.depth == b.depth && a.index < b.index); });
  const Vec3 light = Vec3(-0.4, -1.0, 0.6).normalized();
  char buf[160];
  for (const Face& f : faces) {
    const auto& t = mesh.faces[f.index];
    const Vec3 &a = mesh.vertices[static_cast<std::size_t>(t[0])], &b = mesh.vertices[static_cast<std::size_t>(t[1])],
               &c = mesh.vertices[static_cast<std::size_t>(t[2])];
    const double shade = 0.35 + 0.65 * std::max(0.0, (b - a).cross(c - a).normalized().dot(light));
    const bool berry = mesh.face_part[f.index] == Part::Berry;
    const int r = static_cast<int>((berry ? 120 : 110) * shade), g = static_cast<int>((berry ? 40 : 130) * shade),
              bl = static_cast<int>((berry ? 90 : 60) * shade);
    std::snprintf(buf, sizeof buf, "<polygon points=\"%.1f,%.1f %.1f,%.1f %.1f,%.1f\" fill=\"rgb(%d,%d,%d)\" stroke=\"rgb(%d,%d,%d)\" stroke-width=\"0.4\"/>",
                  px(a.x() * 1e3, 0), py(a.z() * 1e3), px(b.x() * 1e3, 0), py(b.z() * 1e3), px(c.x() * 1e3, 0),
                  py(c.z() * 1e3), r, g, bl, r, g, bl);
    o << buf;
  }
  o << "\n";
  std::vector<std::size_t> order(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return points[i][1] > points[j][1] || (points[i][1] == points[j][1] && i < j); });
  double y0 = 1e9, y1 = -1e9;
  for (const auto& p : points) y0 = std::min(y0, double(p[1])), y1 = std::max(y1, double(p[1]));
  for (std::size_t i : order) {
    const auto& p = points[i];
    const double near = y1 > y0 ? (y1 - p[1]) / (y1 - y0) : 1;  // 1: nearest the viewer
    std::snprintf(buf, sizeof buf, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"1.3\" fill=\"rgb(%d,%d,%d)\"/>",
                  px(p[0], panel), py(p[2]), static_cast<int>(40 + 180 * near), 60, static_cast<int>(200 - 150 * near));
    o << buf;
  }
  o << "\n</svg>\n";
  return o.str();
}

std::string slurp_text(const char* path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return in ? s.str() : std::string();
}

// The run's first bunch: a side view of its mesh and registered scan, and (with
// Debian's libjs-three) an interactive 3D view of the scan against the mesh, inlined.
void first_bunch_section(const ReportContext& ctx, Report& rep, std::ostringstream& h) {
  [[maybe_unused]] const auto& [set, cases, scores, size_cells, eq] = ctx;
  const CaseResult* first = nullptr;
  for (const auto& c : cases) {
    if (c.condition == 0 && c.bunch == 0 && !c.preview_points.empty()) first = &c;
  }
  if (!first) return;
  const TriMesh mesh = first_bunch_mesh(set);
  h << "<h2>The first bunch and its scan</h2>\n<p>Bunch 0 of " << esc(set.conditions[0].label.empty() ? "the run" : set.conditions[0].label)
    << " (" << esc(first->preset) << ", seed " << first->seed << "): its ground-truth mesh (" << mesh.faces.size()
    << " triangles at icosphere level 1) and the registered cloud the estimators measured (" << first->points
    << " points, " << first->preview_points.size() << " shown), in the cloud's frame (the world frame when the "
    << "registration holds; the mesh is always in the world frame).</p>\n";
  const std::string svg = side_view_svg(mesh, first->preview_points);
  rep.svgs["first_bunch_side_view.svg"] = svg;
  h << svg;
  const std::string three = slurp_text("/usr/share/javascript/three/three.min.js");
  const std::string orbit = slurp_text("/usr/share/javascript/three/examples/js/controls/OrbitControls.js");
  if (three.empty() || orbit.empty()) {
    h << "<p>No 3D view: Debian's libjs-three is not installed (scripts/setup.sh installs it).</p>\n";
    return;
  }
  std::ostringstream data;
  data << "{\"vertices\":[";
  char buf[64];
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%s%.1f,%.1f,%.1f", i ? "," : "", mesh.vertices[i].x() * 1e3, mesh.vertices[i].y() * 1e3,
                  mesh.vertices[i].z() * 1e3);
    data << buf;
  }
  data << "],\"faces\":[";
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    data << (f ? "," : "") << mesh.faces[f][0] << "," << mesh.faces[f][1] << "," << mesh.faces[f][2];
  }
  data << "],\"points\":[";
  for (std::size_t i = 0; i < first->preview_points.size(); ++i) {
    const auto& p = first->preview_points[i];
    std::snprintf(buf, sizeof buf, "%s%.1f,%.1f,%.1f", i ? "," : "", p[0], p[1], p[2]);
    data << buf;
  }
  data << "]}";
  h << "<p>Drag to turn, scroll to zoom; red: the scan, grey: the ground-truth surface. <label><input type=checkbox "
       "id=viewer-mesh checked> mesh</label></p>\n<div id=viewer style=\"width:800px;height:560px;border:1px solid #ccc\"></div>\n"
       "<script>" << three << "\n</script>\n<script>" << orbit << "\n</script>\n<script>\n"
       "(function(){var data=" << data.str() << ";\n"
       "var host=document.getElementById('viewer');var probe=document.createElement('canvas');\n"
       "if(!(probe.getContext('webgl')||probe.getContext('experimental-webgl'))){host.textContent='No WebGL in this browser: "
       "the 3D view cannot be shown.';document.body.setAttribute('data-viewer','no-webgl');return;}\n"
       "var scene=new THREE.Scene();scene.background=new THREE.Color(0xffffff);\n"
       "var g=new THREE.BufferGeometry();g.setAttribute('position',new THREE.Float32BufferAttribute(data.vertices,3));\n"
       "g.setIndex(data.faces);g.computeVertexNormals();g.computeBoundingSphere();\n"
       "var mesh=new THREE.Mesh(g,new THREE.MeshLambertMaterial({color:0x9a9a9a,transparent:true,opacity:0.55}));scene.add(mesh);\n"
       "var pg=new THREE.BufferGeometry();pg.setAttribute('position',new THREE.Float32BufferAttribute(data.points,3));\n"
       "scene.add(new THREE.Points(pg,new THREE.PointsMaterial({color:0xd62728,size:2.5,sizeAttenuation:false})));\n"
       "scene.add(new THREE.AmbientLight(0xffffff,0.5));var light=new THREE.DirectionalLight(0xffffff,0.7);"
       "light.position.set(-300,-600,500);scene.add(light);\n"
       "var s=g.boundingSphere;var camera=new THREE.PerspectiveCamera(40,host.clientWidth/host.clientHeight,1,100000);\n"
       "camera.up.set(0,0,1);camera.position.set(s.center.x,s.center.y-3.2*s.radius,s.center.z+0.8*s.radius);\n"
       "var renderer=new THREE.WebGLRenderer({antialias:true});renderer.setSize(host.clientWidth,host.clientHeight);\n"
       "host.appendChild(renderer.domElement);var controls=new THREE.OrbitControls(camera,renderer.domElement);\n"
       "controls.target.copy(s.center);controls.update();\n"
       "document.getElementById('viewer-mesh').addEventListener('change',function(e){mesh.visible=e.target.checked;draw();});\n"
       "function draw(){renderer.render(scene,camera);}controls.addEventListener('change',draw);draw();\n"
       "document.body.setAttribute('data-viewer','drawn');})();\n</script>\n";
}

// The page's self-check, run once everything loaded: how many plots drew with a size,
// and the script errors; written into the body's data attributes and a footer line.
void page_end([[maybe_unused]] const ReportContext& ctx, [[maybe_unused]] Report& rep, std::ostringstream& h) {
  h << "<p id=report-check></p>\n<script>window.addEventListener('load',function(){"
       "var drawn=0;document.querySelectorAll('svg').forEach(function(s){var b=s.getBoundingClientRect();"
       "if(b.width>0&&b.height>0&&s.querySelector('text'))drawn++;});"
       "document.body.setAttribute('data-plots',String(drawn));"
       "document.body.setAttribute('data-errors',String(window.reportErrors.length));"
       "document.getElementById('report-check').textContent=drawn+' plots drawn; script errors: '+"
       "(window.reportErrors.length?window.reportErrors.join('; '):'none');});</script>\n</body></html>\n";
}

}  // namespace

Report make_report(const SceneSet& set, const std::vector<CaseResult>& cases, const std::vector<ScoreRow>& scores,
                   const std::vector<SizeErrorCell>& size_cells) {
  ReportContext ctx{set, cases, scores, size_cells, {}};
  for (const auto& r : scores) {
    if (std::find(ctx.eq.begin(), ctx.eq.end(), std::make_pair(r.estimator, r.quantity)) == ctx.eq.end()) {
      ctx.eq.emplace_back(r.estimator, r.quantity);
    }
  }
  Report rep;
  std::ostringstream h;
  for (auto section : {header, scores_section, comparisons_section, pipeline_section, stereo_section,
                       classification_section, error_distribution_section, first_bunch_section, scatter_section,
                       sweep_section, size_error_section, timing_section, failures_section, page_end}) {
    section(ctx, rep, h);
  }
  rep.html = h.str();
  return rep;
}

}  // namespace grapebench
