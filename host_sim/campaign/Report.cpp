#include "host_sim/campaign/Report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "host_sim/campaign/Runner.hpp"
#include "host_sim/output/PlotUtil.hpp"
#include "loader/AtomicWrite.hpp"

namespace carril::sim::campaign {

namespace {
namespace fs = std::filesystem;

struct Metric {
  const char* key;
  const char* label;
};
// The distributions the report shows.
constexpr Metric kMetrics[] = {{"cross_track_rms_m", "cross-track RMS [m]"},
                               {"end_stop_error_m", "end stop error [m]"},
                               {"sim_time_s", "simulated time [s]"}};
constexpr int kBins = 5;  // perturbation bins
constexpr int kWorstRuns = 10;

std::optional<double> number(const RunRow& r, const char* key) {
  const std::string& s = r.field(key);
  if (s.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0' || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string pct(std::uint64_t k, std::uint64_t n) {
  if (n == 0) return "-";
  const Interval ci = wilson95(k, n);
  return fmt("%.1f %%", 100.0 * double(k) / double(n)) + " [" + fmt("%.1f", 100.0 * ci.lo) + ", " +
         fmt("%.1f", 100.0 * ci.hi) + "]";
}

std::string pair_name(const RunRow& r) {
  return r.preset.empty() ? std::string("its own robot") : r.preset + " + `" + r.strategy + "`";
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double pos = q * double(v.size() - 1);
  const std::size_t i = std::size_t(pos);
  const double f = pos - double(i);
  return i + 1 < v.size() ? v[i] * (1.0 - f) + v[i + 1] * f : v[i];
}

std::string how_it_ended(const RunRow& r) {
  if (!r.failed() && !r.passed()) {
    return r.status.rfind("signal", 0) == 0 ? "crashed (" + r.status + ")"
                                            : "refused its input (" + r.status + ")";
  }
  std::string s = r.field("result") + ", final state " + r.field("final_state");
  if (!r.field("fault").empty()) s += ", fault " + r.field("fault");
  return s;
}

std::string first_unmet(const RunRow& r) {
  std::string s = r.field("unmet_expectations");
  const std::size_t semi = s.find(';');
  if (semi != std::string::npos) s.resize(semi);
  // "max_cross_track_rms_m: expected <= 0.03, got 0.05": the expectation's name.
  const std::size_t colon = s.find(':');
  return colon == std::string::npos ? s : s.substr(0, colon);
}

// Bins of a perturbation's values: [lo, hi] split in kBins; a constant value is one bin.
struct Bins {
  double lo = 0.0, hi = 0.0;
  int count = 1;
  int of(double v) const {
    if (count == 1 || hi <= lo) return 0;
    return std::clamp(int((v - lo) / (hi - lo) * count), 0, count - 1);
  }
  double edge(int b) const { return lo + (hi - lo) * b / count; }
};

// A bar chart of pass rates with their intervals, one bar per bin.
cv::Mat pass_rate_plot(const std::string& title, const Bins& bins,
                       const std::vector<std::uint64_t>& k, const std::vector<std::uint64_t>& n) {
  const int w = 640, h = 360, left = 60, right = 20, top = 40, bottom = 60;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar ink(40, 40, 40), grid(220, 220, 220);
  plot::put_text(img, title, {left, 25}, 0.55, ink, w - left - right);
  const int pw = w - left - right, ph = h - top - bottom;
  for (int t = 0; t <= 4; ++t) {
    const int y = top + ph - ph * t / 4;
    cv::line(img, {left, y}, {left + pw, y}, grid, 1);
    plot::put_text(img, fmt("%.0f %%", 25.0 * t), {5, y + 5}, 0.4, ink);
  }
  const int nb = int(n.size());
  for (int b = 0; b < nb; ++b) {
    const int x0 = left + pw * b / nb + 6, x1 = left + pw * (b + 1) / nb - 6;
    std::string label = bins.count == 1
                            ? fmt("%g", bins.lo)
                            : fmt("%.3g", bins.edge(b)) + ".." + fmt("%.3g", bins.edge(b + 1));
    plot::put_text(img, label, {x0, top + ph + 18}, 0.38, ink, x1 - x0);
    plot::put_text(img, "n=" + std::to_string(n[std::size_t(b)]), {x0, top + ph + 36}, 0.38, ink);
    if (n[std::size_t(b)] == 0) continue;
    const double rate = double(k[std::size_t(b)]) / double(n[std::size_t(b)]);
    const Interval ci = wilson95(k[std::size_t(b)], n[std::size_t(b)]);
    const int y = top + ph - int(std::lround(rate * ph));
    cv::rectangle(img, {x0, y}, {x1, top + ph},
                  rate >= 0.99 ? cv::Scalar(120, 190, 90) : cv::Scalar(80, 110, 230), cv::FILLED);
    const int xm = (x0 + x1) / 2;
    const int ylo = top + ph - int(std::lround(ci.lo * ph)),
              yhi = top + ph - int(std::lround(ci.hi * ph));
    cv::line(img, {xm, ylo}, {xm, yhi}, ink, 1);
    cv::line(img, {xm - 5, ylo}, {xm + 5, ylo}, ink, 1);
    cv::line(img, {xm - 5, yhi}, {xm + 5, yhi}, ink, 1);
  }
  cv::rectangle(img, {left, top}, {left + pw, top + ph}, ink, 1);
  return img;
}

// A histogram of a metric over the runs, passed and not passed stacked.
cv::Mat histogram_plot(const std::string& title, const std::vector<double>& pass,
                       const std::vector<double>& fail) {
  const int w = 640, h = 360, left = 50, right = 20, top = 40, bottom = 40, nb = 20;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar ink(40, 40, 40);
  plot::put_text(img, title, {left, 25}, 0.55, ink, w - left - right);
  double lo = INFINITY, hi = -INFINITY;
  for (const auto* v : {&pass, &fail}) {
    for (const double x : *v) {
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  }
  const int pw = w - left - right, ph = h - top - bottom;
  cv::rectangle(img, {left, top}, {left + pw, top + ph}, ink, 1);
  if (!(hi >= lo)) return img;
  if (hi == lo) hi = lo + 1.0;
  std::vector<int> cp(nb, 0), cf(nb, 0);
  const auto bin = [&](double x) { return std::clamp(int((x - lo) / (hi - lo) * nb), 0, nb - 1); };
  for (const double x : pass) ++cp[std::size_t(bin(x))];
  for (const double x : fail) ++cf[std::size_t(bin(x))];
  int peak = 1;
  for (int b = 0; b < nb; ++b) peak = std::max(peak, cp[std::size_t(b)] + cf[std::size_t(b)]);
  for (int b = 0; b < nb; ++b) {
    const int x0 = left + pw * b / nb + 1, x1 = left + pw * (b + 1) / nb - 1;
    const int yp = top + ph - ph * cp[std::size_t(b)] / peak;
    const int yf = yp - ph * cf[std::size_t(b)] / peak;
    cv::rectangle(img, {x0, yp}, {x1, top + ph}, cv::Scalar(120, 190, 90), cv::FILLED);
    if (cf[std::size_t(b)] > 0)
      cv::rectangle(img, {x0, yf}, {x1, yp}, cv::Scalar(80, 110, 230), cv::FILLED);
  }
  plot::put_text(img, fmt("%.4g", lo), {left, top + ph + 18}, 0.4, ink);
  plot::put_text(img, fmt("%.4g", hi), {left + pw - 60, top + ph + 18}, 0.4, ink);
  plot::put_text(img, "runs: " + std::to_string(peak) + " at most per bin; green passed, red not",
                 {left + 90, top + ph + 18}, 0.4, ink, pw - 180);
  return img;
}

struct Png {
  std::string name;
  cv::Mat img;
};

// The Markdown, and the plots it links to (in `pngs`).
std::string build(const CampaignSpec& spec, const ResultsTable& t, const std::string& out_dir,
                  const std::string& sim_command, std::vector<Png>* pngs) {
  std::string md = "# Campaign " + spec.name + "\n\n";
  std::uint64_t passed = 0, failed = 0, errors = 0;
  for (const RunRow& r : t.rows) {
    passed += r.passed();
    failed += r.failed();
    errors += !r.passed() && !r.failed();
  }
  const std::uint64_t n = t.rows.size();
  md += "Campaign file `" + spec.path + "`, seed " + std::to_string(spec.seed) + ": " +
        std::to_string(spec.variant_count()) + " variants, " + std::to_string(n) + " finished";
  if (t.missing > 0) md += " (" + std::to_string(t.missing) + " not yet: this report is partial)";
  md += ".\n\n**Pass rate: " + pct(passed, n) +
        "** (95 % Wilson interval in brackets): " + std::to_string(passed) + " passed, " +
        std::to_string(failed) + " missed their expectations, " + std::to_string(errors) +
        " did not run to the end (refused input or crash).\n\n";

  // Per base scenario and pair.
  md +=
      "## Pass rate per scenario and robot\n\n| scenario | robot + strategy | runs | passed | "
      "pass rate [95 % CI] |\n| --- | --- | --- | --- | --- |\n";
  std::map<std::pair<std::string, std::string>, std::pair<std::uint64_t, std::uint64_t>> groups;
  for (const RunRow& r : t.rows) {
    auto& g = groups[{r.base_name, pair_name(r)}];
    g.first += r.passed();
    ++g.second;
  }
  for (const auto& [key, g] : groups) {
    md += "| " + key.first + " | " + key.second + " | " + std::to_string(g.second) + " | " +
          std::to_string(g.first) + " | " + pct(g.first, g.second) + " |\n";
  }

  // Failure modes.
  md += "\n## Failure modes\n\n";
  std::map<std::string, std::pair<std::uint64_t, std::uint64_t>> modes;  // count, first index
  for (const RunRow& r : t.rows) {
    if (r.passed()) continue;
    std::string key = how_it_ended(r);
    const std::string u = first_unmet(r);
    if (!u.empty()) key += " | missed " + u;
    auto [it, fresh] = modes.try_emplace(key, 0, r.index);
    ++it->second.first;
  }
  if (modes.empty()) {
    md += "Every run passed.\n";
  } else {
    std::vector<std::pair<std::string, std::pair<std::uint64_t, std::uint64_t>>> sorted(
        modes.begin(), modes.end());
    std::stable_sort(sorted.begin(), sorted.end(),
                     [](const auto& a, const auto& b) { return a.second.first > b.second.first; });
    md +=
        "| how it ended | first missed expectation | runs | e.g. variant |\n| --- | --- | --- | "
        "--- "
        "|\n";
    for (const auto& [key, c] : sorted) {
      const std::size_t bar = key.find(" | missed ");
      const std::string ended = key.substr(0, bar);
      const std::string missed = bar == std::string::npos ? "-" : "`" + key.substr(bar + 10) + "`";
      md += "| " + ended + " | " + missed + " | " + std::to_string(c.first) + " | " +
            std::to_string(c.second) + " |\n";
    }
  }

  // Metric distributions.
  md +=
      "\n## Metrics\n\nMedian / 90th percentile / maximum over the runs that have the metric.\n\n"
      "| scenario | robot + strategy |";
  for (const Metric& m : kMetrics) md += std::string(" ") + m.label + " |";
  md += "\n| --- | --- |";
  for (std::size_t k = 0; k < std::size(kMetrics); ++k) md += " --- |";
  md += "\n";
  for (const auto& [key, g] : groups) {
    md += "| " + key.first + " | " + key.second + " |";
    for (const Metric& m : kMetrics) {
      std::vector<double> v;
      for (const RunRow& r : t.rows) {
        if (r.base_name != key.first || pair_name(r) != key.second) continue;
        if (auto x = number(r, m.key)) v.push_back(*x);
      }
      md += v.empty()
                ? std::string(" - |")
                : " " + fmt("%.4g", quantile(v, 0.5)) + " / " + fmt("%.4g", quantile(v, 0.9)) +
                      " / " + fmt("%.4g", quantile(v, 1.0)) + " |";
    }
    md += "\n";
  }
  md += "\n";
  for (const Metric& m : kMetrics) {
    std::vector<double> p, f;
    for (const RunRow& r : t.rows) {
      if (auto x = number(r, m.key)) (r.passed() ? p : f).push_back(*x);
    }
    if (p.empty() && f.empty()) continue;
    const std::string name = std::string("metric_") + m.key + ".png";
    if (pngs) pngs->push_back({name, histogram_plot(m.label, p, f)});
    md += "![" + std::string(m.label) + "](report/" + name + ")\n";
  }

  // Perturbations.
  md += "\n## Pass rate against each perturbation\n\n";
  if (spec.perturbations.empty()) md += "The campaign perturbs nothing.\n";
  struct Effect {
    std::size_t p;
    double worst_rate;
    std::string worst_bin;
  };
  std::vector<Effect> effects;
  const double overall = n == 0 ? 0.0 : double(passed) / double(n);
  for (std::size_t p = 0; p < spec.perturbations.size(); ++p) {
    Bins b;
    b.lo = INFINITY;
    b.hi = -INFINITY;
    for (const RunRow& r : t.rows) {
      b.lo = std::min(b.lo, r.values[p]);
      b.hi = std::max(b.hi, r.values[p]);
    }
    if (t.rows.empty()) continue;
    b.count = b.hi > b.lo ? kBins : 1;
    std::vector<std::uint64_t> k(std::size_t(b.count), 0), m(std::size_t(b.count), 0);
    for (const RunRow& r : t.rows) {
      const int i = b.of(r.values[p]);
      k[std::size_t(i)] += r.passed();
      ++m[std::size_t(i)];
    }
    const std::string& key = spec.perturbations[p].key;
    const std::string name = "perturbation_" + key + ".png";
    if (pngs) pngs->push_back({name, pass_rate_plot("pass rate against " + key, b, k, m)});
    Effect e{p, 1.0, ""};
    for (int i = 0; i < b.count; ++i) {
      if (m[std::size_t(i)] == 0) continue;
      const double rate = double(k[std::size_t(i)]) / double(m[std::size_t(i)]);
      if (rate < e.worst_rate || e.worst_bin.empty()) {
        e.worst_rate = rate;
        e.worst_bin = b.count == 1 ? fmt("%g", b.lo)
                                   : fmt("%.4g", b.edge(i)) + " to " + fmt("%.4g", b.edge(i + 1));
        e.worst_bin += " (" + pct(k[std::size_t(i)], m[std::size_t(i)]) + ", " +
                       std::to_string(m[std::size_t(i)]) + " runs)";
      }
    }
    effects.push_back(e);
  }
  std::stable_sort(effects.begin(), effects.end(),
                   [](const Effect& a, const Effect& b) { return a.worst_rate < b.worst_rate; });
  if (!effects.empty()) {
    md +=
        "Ranked by their worst bin (of " + std::to_string(kBins) +
        " equal bins over the values drawn); the overall rate is " +
        fmt("%.1f %%", 100.0 * overall) +
        ".\n\n| perturbation | worst bin (pass rate [95 % CI], runs) | below overall by |\n| --- | "
        "--- | --- |\n";
    for (const Effect& e : effects) {
      md += "| `" + spec.perturbations[e.p].key + "` | " + e.worst_bin + " | " +
            fmt("%.1f", 100.0 * std::max(0.0, overall - e.worst_rate)) + " points |\n";
    }
    md += "\n";
    for (const Effect& e : effects) {
      const std::string& key = spec.perturbations[e.p].key;
      md += "![" + key + "](report/perturbation_" + key + ".png)\n";
    }
  }

  // Worst runs: not run to the end first, then missed expectations, each by cross-track RMS.
  md += "\n## The worst runs\n\n";
  std::vector<const RunRow*> worst;
  for (const RunRow& r : t.rows) worst.push_back(&r);
  const auto rank = [](const RunRow& r) { return r.passed() ? 2 : r.failed() ? 1 : 0; };
  std::stable_sort(worst.begin(), worst.end(), [&](const RunRow* a, const RunRow* b) {
    if (rank(*a) != rank(*b)) return rank(*a) < rank(*b);
    return number(*a, "cross_track_rms_m").value_or(0.0) >
           number(*b, "cross_track_rms_m").value_or(0.0);
  });
  if (worst.size() > std::size_t(kWorstRuns)) worst.resize(kWorstRuns);
  md +=
      "Not run to the end first, then missed expectations, then by cross-track RMS.\n\n"
      "| variant | scenario | robot + strategy | how it ended | cross-track RMS [m] | replay |\n"
      "| --- | --- | --- | --- | --- | --- |\n";
  for (const RunRow* r : worst) {
    const std::string rms = r->field("cross_track_rms_m");
    std::string ended = r->passed() ? "passed" : how_it_ended(*r);
    const std::string u = first_unmet(*r);
    if (!u.empty()) ended += "; missed `" + u + "`";
    md += "| " + std::to_string(r->index) + " | " + r->base_name + " | " + pair_name(*r) + " | " +
          ended + " | " + (rms.empty() ? "-" : rms) + " | `" + sim_command + " --scenario " +
          (fs::path(variant_dir(out_dir, r->index)) / "scenario.yaml").string() + " --view` |\n";
  }
  return md;
}
}  // namespace

Interval wilson95(std::uint64_t k, std::uint64_t n) {
  if (n == 0) return {};
  const double z = 1.959963984540054, nn = double(n), p = double(k) / nn;
  const double denom = 1.0 + z * z / nn;
  const double centre = (p + z * z / (2.0 * nn)) / denom;
  const double half = z * std::sqrt(p * (1.0 - p) / nn + z * z / (4.0 * nn * nn)) / denom;
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

std::string report_markdown(const CampaignSpec& spec, const ResultsTable& t,
                            const std::string& out_dir, const std::string& sim_command) {
  return build(spec, t, out_dir, sim_command, nullptr);
}

ReportResult write_report(const CampaignSpec& spec, const ResultsTable& t,
                          const std::string& out_dir, const std::string& sim_command) {
  ReportResult r;
  std::vector<Png> pngs;
  const std::string md = build(spec, t, out_dir, sim_command, &pngs);
  const fs::path dir = fs::path(out_dir) / "report";
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    r.error = dir.string() + ": cannot create: " + ec.message();
    return r;
  }
  for (const Png& p : pngs) {
    std::string bytes;
    if (!plot::encode_png(p.img, bytes, r.error)) return r;
    if (auto e = loader::write_file_atomically((dir / p.name).string(), bytes)) {
      r.error = *e;
      return r;
    }
  }
  if (auto e = loader::write_file_atomically((fs::path(out_dir) / "report.md").string(), md)) {
    r.error = *e;
    return r;
  }
  r.ok = true;
  return r;
}

}  // namespace carril::sim::campaign
