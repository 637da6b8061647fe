// The study's verdict tables (summary), summary.md and study.html (see study/study.h).
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/study/study.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

namespace msh::study {

using json = nlohmann::json;

namespace {

// The terms of a run, in the study's order (results.json "config.terms").
std::vector<std::string> methods_of(const json& results) {
  return results["config"]["terms"].get<std::vector<std::string>>();
}
const std::vector<std::string> kComponents = {"total", "diffuse", "specular"};

bool is_num(const json& j) { return j.is_number(); }

// Mean of a list (NaN when empty).
struct Acc {
  double s = 0;
  int n = 0;
  double mx = 0;
  void add(double x) {
    s += x, ++n;
    mx = std::max(mx, x);
  }
  double mean() const { return n ? s / n : std::nan(""); }
};

struct MethodAcc {
  Acc bias, dev, fp, bias_floor, fp_floor;
};

// A row's fields joined (a field it lacks, as in rows from before views were added, counts as null).
std::string key_of(const json& r, std::initializer_list<const char*> keys) {
  std::string k;
  for (const char* s : keys) k += (r.contains(s) ? r[s].dump() : std::string("null")) + "|";
  return k;
}
json field(const json& r, const char* key) { return r.contains(key) ? r[key] : json(nullptr); }

// summarize's "cells": per cell each term's mean bias, |bias - 1|, footprint RMSE and floors, and the terms
// within delta of the best.
json cells_json(const std::map<std::string, std::map<std::string, MethodAcc>>& cells,
                const std::map<std::string, json>& cell_info, const StudyConfig& cfg) {
  json jc = json::array();
  for (const auto& [k, ms] : cells) {
    json c = cell_info.at(k);
    json jm = json::object();
    double best_dev = 1e300, best_fp = 1e300;
    for (const auto& [m, a] : ms) {
      jm[m] = {{"bias", a.bias.mean()},
               {"abs_dev", a.dev.mean()},
               {"rmse_footprint_rel", a.fp.mean()},
               {"bias_floor", a.bias_floor.mx},
               {"rmse_footprint_floor_rel", a.fp_floor.mx},
               {"n", a.bias.n}};
      best_dev = std::min(best_dev, a.dev.mean()), best_fp = std::min(best_fp, a.fp.mean());
    }
    json bb = json::array(), br = json::array();
    for (const auto& [m, a] : ms) {
      if (a.dev.mean() <= best_dev + cfg.delta_bias) bb.push_back(m);
      if (a.fp.mean() <= best_fp + cfg.delta_rmse) br.push_back(m);
    }
    c["methods"] = jm, c["best_bias"] = bb, c["best_rmse_footprint"] = br;
    jc.push_back(c);
  }
  return jc;
}

// summarize's "by_view": per view × component × scale × method, over the directional lights of every material
// (both grids): mean and largest |bias - 1| of the per-material cells.
json by_view_json(const json& jc) {
  std::map<std::string, std::pair<json, Acc>> by_view;
  for (const json& c : jc) {
    if (c["material"] == "all" || c["light_type"] != "directional") continue;
    for (const auto& [m, e] : c["methods"].items()) {
      const double d = e["abs_dev"].get<double>();
      if (!std::isfinite(d)) continue;
      auto& [info, acc] = by_view[key_of(c, {"view", "view_azimuth", "component", "scale"}) + m];
      info = {{"view", c["view"]},
              {"view_azimuth", c["view_azimuth"]},
              {"component", c["component"]},
              {"scale", c["scale"]},
              {"method", m}};
      acc.add(d);
    }
  }
  json bv = json::array();
  for (auto& [k, p] : by_view) {
    json e = p.first;
    e["mean_abs_dev"] = p.second.mean(), e["max_abs_dev"] = p.second.mx, e["n"] = p.second.n;
    bv.push_back(e);
  }
  return bv;
}

}  // namespace

json summarize(const json& rows, const StudyConfig& cfg) {
  // The total component's mean radiance per configuration: components below 2% of it are negligible.
  std::map<std::string, double> total_mean;
  for (const auto& r : rows)
    if (r["component"] == "total" && r["method"] == "none" && r["ms_normal"] == "shading" &&
        r["roughness"] == "base" && is_num(r["gt_mean"]["whole"]))
      total_mean[key_of(r, {"material", "shape", "scale", "view", "view_azimuth", "light"})] =
          r["gt_mean"]["whole"].get<double>();
  auto usable = [&](const json& r) {
    if (!is_num(r["bias"]["whole"]) || !is_num(r["gt_mean"]["whole"])) return false;
    const auto it =
        total_mean.find(key_of(r, {"material", "shape", "scale", "view", "view_azimuth", "light"}));
    return it != total_mean.end() && r["gt_mean"]["whole"].get<double>() >= 0.02 * it->second;
  };

  // cells[material or "all"][component, scale, light][method]
  std::map<std::string, std::map<std::string, MethodAcc>> cells;
  std::map<std::string, json> cell_info;
  std::map<std::string, std::map<std::string, std::pair<Acc, Acc>>> ablation, widened;
  std::map<std::string, json> abl_info;
  for (const auto& r : rows) {
    if (!usable(r)) continue;
    // The area-light section's representative / integrated rows are compared in area_summary only.
    if (r.contains("area_ms") && r["area_ms"] != "sampled") continue;
    const double b = r["bias"]["whole"].get<double>(), gm = r["gt_mean"]["whole"].get<double>();
    const double dev = std::abs(b - 1);
    const double fp =
        is_num(r["rmse_footprint"]["whole"]) ? r["rmse_footprint"]["whole"].get<double>() / gm : 0;
    const double fpf = is_num(r["rmse_footprint_floor"]["whole"])
                           ? r["rmse_footprint_floor"]["whole"].get<double>() / gm
                           : 0;
    const double bf = is_num(r["bias_stderr"]["whole"]) ? r["bias_stderr"]["whole"].get<double>() : 0;
    const std::string ck = key_of(r, {"component", "scale", "view", "view_azimuth", "light"});
    const std::string m = r["method"];
    if (r["ms_normal"] == "shading" && r["roughness"] == "base") {
      for (const std::string& mat : {std::string("all"), r["material"].get<std::string>()}) {
        const std::string k = mat + "|" + ck;
        MethodAcc& a = cells[k][m];
        a.bias.add(b), a.dev.add(dev), a.fp.add(fp), a.bias_floor.add(bf), a.fp_floor.add(fpf);
        cell_info[k] = {{"material", mat},
                        {"component", r["component"]},
                        {"scale", r["scale"]},
                        {"view", field(r, "view")},
                        {"view_azimuth", field(r, "view_azimuth")},
                        {"grid", r.contains("grid") ? r["grid"] : json("main")},
                        {"light", r["light"]},
                        {"light_type", field(r, "light_type")},
                        {"elevation", r["elevation"]}};
      }
    }
    abl_info[ck] = {{"component", r["component"]}, {"scale", r["scale"]},
                    {"view", field(r, "view")},    {"view_azimuth", field(r, "view_azimuth")},
                    {"light", r["light"]},         {"elevation", r["elevation"]}};
    if (r["roughness"] == "base" && m != "none" && m != "ao")
      (r["ms_normal"] == "smooth" ? ablation[ck][m].second : ablation[ck][m].first).add(dev);
    if (r["ms_normal"] == "shading" && r["scale"].get<int>() > 1)
      (r["roughness"] == "widened" ? widened[ck][m].second : widened[ck][m].first).add(dev);
  }

  json out = {{"delta_bias", cfg.delta_bias}, {"delta_rmse", cfg.delta_rmse}};
  const json jc = cells_json(cells, cell_info, cfg);
  out["cells"] = jc;
  out["by_view"] = by_view_json(jc);
  // Per cell, each term's mean |bias - 1| in two conditions (first, second), for the terms measured in both;
  // `more` adds cell-level fields from the same pairs.
  auto paired = [&](const auto& by_cell, const char* first, const char* second, auto&& more) {
    json arr = json::array();
    for (const auto& [k, ts] : by_cell) {
      json a = abl_info[k];
      json jt = json::object();
      for (const auto& [m, p] : ts)
        if (p.first.n && p.second.n) jt[m] = {{first, p.first.mean()}, {second, p.second.mean()}};
      a["terms"] = jt;
      more(a, ts);
      arr.push_back(a);
    }
    return arr;
  };
  out["normal_ablation"] = paired(ablation, "shading", "smooth", [&](json& a, const auto& ts) {
    int closer = 0, farther = 0, n = 0;
    Acc sh, sm;
    for (const auto& [m, p] : ts) {
      if (!p.first.n || !p.second.n) continue;
      closer += p.second.mean() < p.first.mean() - cfg.delta_bias;
      farther += p.second.mean() > p.first.mean() + cfg.delta_bias;
      ++n, sh.add(p.first.mean()), sm.add(p.second.mean());
    }
    a["smooth_closer"] = closer, a["smooth_farther"] = farther, a["of"] = n;
    a["shading_abs_dev"] = sh.mean(), a["smooth_abs_dev"] = sm.mean();
  });
  out["widened_roughness"] = paired(widened, "base", "widened", [](json&, const auto&) {});
  return out;
}

namespace {

// One table for both outputs.
struct Table {
  std::string title, note;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::vector<bool>> bold;
};

std::string md(const Table& t) {
  std::string s = "#### " + t.title + "\n\n";
  if (!t.note.empty()) s += t.note + "\n\n";
  s += "|";
  for (const auto& h : t.header) s += " " + h + " |";
  s += "\n|";
  for (std::size_t i = 0; i < t.header.size(); ++i) s += i == 0 ? "---|" : "---:|";
  s += "\n";
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    s += "|";
    for (std::size_t c = 0; c < t.rows[r].size(); ++c)
      s += " " + (t.bold[r][c] ? "**" + t.rows[r][c] + "**" : t.rows[r][c]) + " |";
    s += "\n";
  }
  return s + "\n";
}

// Text and quoted attribute values: the five characters HTML gives meaning to, as entities.
std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<')
      o += "&lt;";
    else if (c == '>')
      o += "&gt;";
    else if (c == '&')
      o += "&amp;";
    else if (c == '\'')
      o += "&#39;";
    else if (c == '"')
      o += "&quot;";
    else
      o += c;
  }
  return o;
}

// A relative file path as a URL (RFC 3986): every byte but the unreserved characters and '/' percent-encoded,
// so a file name of the user's (a material is named after its height map) cannot end the attribute or turn
// into a scheme; safe inside a quoted attribute as is.
std::string url_path(const std::string& p) {
  std::string o;
  for (unsigned char c : p) {
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~' || c == '/')
      o += char(c);
    else
      o += fmt::format("%{:02X}", unsigned(c));
  }
  return o;
}

std::string html(const Table& t) {
  std::string s = "<h4>" + esc(t.title) + "</h4>\n";
  if (!t.note.empty()) s += "<p class=note>" + esc(t.note) + "</p>\n";
  s += "<table><tr>";
  for (const auto& h : t.header) s += "<th>" + esc(h) + "</th>";
  s += "</tr>\n";
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    s += "<tr>";
    for (std::size_t c = 0; c < t.rows[r].size(); ++c)
      s += (t.bold[r][c] ? "<td class=best>" : "<td>") + esc(t.rows[r][c]) + "</td>";
    s += "</tr>\n";
  }
  return s + "</table>\n";
}

std::string f3(double x) { return std::isfinite(x) ? fmt::format("{:.3f}", x) : "–"; }

// The main view: the first of the main grid's views (the verdict tables are of it; "By view" has the rest).
bool main_view(const json& results, const json& c) {
  const json& cfg = results["config"];
  const json v = c.contains("view") ? c["view"] : json(nullptr);
  if (v.is_null() || !cfg.contains("views")) return true;  // results from before views were added
  return v == cfg["views"][0] && c["view_azimuth"] == cfg["view_azimuths"][0] &&
         (!c.contains("grid") || c["grid"] == "main");
}

const json* find_cell(const json& results, const std::string& mat, const std::string& comp, int k,
                      const std::string& light) {
  for (const auto& c : results["summary"]["cells"])
    if (c["material"] == mat && c["component"] == comp && c["scale"] == k && c["light"] == light &&
        main_view(results, c))
      return &c;
  return nullptr;
}

bool contains(const json& arr, const std::string& s) {
  for (const auto& x : arr)
    if (x == s) return true;
  return false;
}

std::vector<std::string> light_names(const json& results) {
  std::vector<std::string> v;
  for (const auto& g : results["ground_truth"]) {
    if (!main_view(results, g)) continue;
    const std::string l = g["light"];
    if (std::find(v.begin(), v.end(), l) == v.end()) v.push_back(l);
  }
  return v;
}

// Methods × lights of one (material, component, scale): bias or relative footprint RMSE; best (ties within
// the ranking resolution) in bold.
Table method_table(const json& results, const std::string& mat, const std::string& comp, int k,
                   bool use_bias) {
  Table t;
  t.title =
      fmt::format("{} — {}, k = {}, {}: {}", use_bias ? "Mean-radiance ratio" : "Footprint RMSE / GT mean",
                  mat == "all" ? "all materials" : mat, k, comp,
                  use_bias ? "term / ground truth (1 = exact)" : "lower is better");
  t.header = {"method"};
  const auto lights = light_names(results);
  for (const auto& l : lights) t.header.push_back(l);
  double floor = 0;
  for (const auto& m : methods_of(results)) {
    std::vector<std::string> row{m};
    std::vector<bool> b{false};
    for (const auto& l : lights) {
      const json* c = find_cell(results, mat, comp, k, l);
      if (!c || !c->at("methods").contains(m)) {
        row.push_back("–"), b.push_back(false);
        continue;
      }
      const json& e = c->at("methods")[m];
      const double v = use_bias ? e["bias"].get<double>() : e["rmse_footprint_rel"].get<double>();
      floor = std::max(
          floor, use_bias ? e["bias_floor"].get<double>() : e["rmse_footprint_floor_rel"].get<double>());
      row.push_back(f3(v));
      b.push_back(contains(c->at(use_bias ? "best_bias" : "best_rmse_footprint"), m));
    }
    t.rows.push_back(row), t.bold.push_back(b);
  }
  t.note = fmt::format(
      "Bold: closest to the ground truth ({} within {} of the best). Largest ground-truth noise floor in "
      "this "
      "table: {:.4f}.",
      use_bias ? "|ratio − 1|" : "footprint RMSE",
      use_bias ? results["summary"]["delta_bias"].get<double>()
               : results["summary"]["delta_rmse"].get<double>(),
      floor);
  return t;
}

// For each scale × light: the closest term(s) per component.
Table best_table(const json& results, bool use_bias) {
  Table t;
  t.title = use_bias ? "Closest mean radiance, by component (all materials)"
                     : "Lowest footprint RMSE, by component (all materials)";
  t.header = {"scale", "light", "total", "diffuse", "specular"};
  for (int k : results["config"]["scales"].get<std::vector<int>>())
    for (const auto& l : light_names(results)) {
      std::vector<std::string> row{fmt::format("k = {}", k), l};
      for (const auto& comp : kComponents) {
        const json* c = find_cell(results, "all", comp, k, l);
        if (!c) {
          row.push_back("(negligible)");
          continue;
        }
        std::string s;
        for (const auto& m : c->at(use_bias ? "best_bias" : "best_rmse_footprint"))
          s += (s.empty() ? "" : ", ") + m.get<std::string>();
        row.push_back(s);
      }
      t.rows.push_back(row), t.bold.push_back(std::vector<bool>(row.size(), false));
    }
  return t;
}

Table ablation_table(const json& results) {
  Table t;
  t.title = "N·L from the shading normal or the unperturbed normal (mean |ratio − 1| over the 7 N·L terms)";
  t.note =
      "Cells: shading / smooth (how many terms the smooth normal brings closer / farther by more than the "
      "ranking resolution). Total component, all materials.";
  t.header = {"scale"};
  const auto lights = light_names(results);
  for (const auto& l : lights) t.header.push_back(l);
  for (int k : results["config"]["scales"].get<std::vector<int>>()) {
    std::vector<std::string> row{fmt::format("k = {}", k)};
    for (const auto& l : lights) {
      std::string s = "–";
      for (const auto& a : results["summary"]["normal_ablation"])
        if (a["component"] == "total" && a["scale"] == k && a["light"] == l && main_view(results, a))
          s = fmt::format("{} / {} ({}↑ {}↓ of {})", f3(a["shading_abs_dev"].get<double>()),
                          f3(a["smooth_abs_dev"].get<double>()), a["smooth_closer"].get<int>(),
                          a["smooth_farther"].get<int>(), a["of"].get<int>());
      row.push_back(s);
    }
    t.rows.push_back(row), t.bold.push_back(std::vector<bool>(row.size(), false));
  }
  return t;
}

Table widened_table(const json& results, const std::string& comp) {
  Table t;
  t.title = "Base vs variance-widened coarse roughness: |ratio − 1|, " + comp + " component (all materials)";
  t.header = {"scale, light"};
  const auto methods = methods_of(results);
  for (const auto& m : methods) t.header.push_back(m);
  for (const auto& a : results["summary"]["widened_roughness"]) {
    if (a["component"] != comp || !main_view(results, a)) continue;
    std::vector<std::string> row{
        fmt::format("k = {}, {}", a["scale"].get<int>(), a["light"].get<std::string>())};
    for (const auto& m : methods)
      row.push_back(a["terms"].contains(m) ? f3(a["terms"][m]["base"].get<double>()) + " / " +
                                                 f3(a["terms"][m]["widened"].get<double>())
                                           : "–");
    t.rows.push_back(row), t.bold.push_back(std::vector<bool>(row.size(), false));
  }
  return t;
}

// Per view: each method's mean (largest) |ratio - 1| over the directional lights of every material, per
// scale (summary "by_view").
Table view_table(const json& results, const std::string& comp) {
  Table t;
  t.title = "By view: mean (largest) |ratio − 1| over the directional lights and materials, " + comp;
  t.note = "View: degrees off the normal / azimuth of the direction to the camera. Both grids' cells.";
  std::vector<int> scales;
  std::vector<std::pair<double, double>> views;
  std::vector<std::string> methods;
  std::map<std::string, const json*> at;
  const json empty = json::array();
  const json& bv = results["summary"].contains("by_view") ? results["summary"]["by_view"] : empty;
  for (const json& e : bv) {
    if (e["component"] != comp || !e["view"].is_number()) continue;
    const int k = e["scale"].get<int>();
    const std::pair<double, double> vw{e["view"].get<double>(), e["view_azimuth"].get<double>()};
    const std::string m = e["method"];
    if (std::find(scales.begin(), scales.end(), k) == scales.end()) scales.push_back(k);
    if (std::find(views.begin(), views.end(), vw) == views.end()) views.push_back(vw);
    if (std::find(methods.begin(), methods.end(), m) == methods.end()) methods.push_back(m);
    at[fmt::format("{}|{}|{}|{}", vw.first, vw.second, k, m)] = &e;
  }
  std::sort(scales.begin(), scales.end());
  std::sort(views.begin(), views.end());
  t.header = {"view", "method"};
  for (int k : scales) t.header.push_back(fmt::format("k = {}", k));
  for (const auto& vw : views)
    for (const auto& m : methods) {
      std::vector<std::string> row{fmt::format("{:g}° / {:g}°", vw.first, vw.second), m};
      bool any = false;
      for (int k : scales) {
        const auto it = at.find(fmt::format("{}|{}|{}|{}", vw.first, vw.second, k, m));
        if (it == at.end()) {
          row.push_back("–");
          continue;
        }
        any = true;
        row.push_back(f3((*it->second)["mean_abs_dev"].get<double>()) + " (" +
                      f3((*it->second)["max_abs_dev"].get<double>()) + ")");
      }
      if (any) t.rows.push_back(row), t.bold.push_back(std::vector<bool>(row.size(), false));
    }
  return t;
}

std::vector<Table> all_tables(const json& results) {
  std::vector<Table> v;
  const auto scales = results["config"]["scales"].get<std::vector<int>>();
  if (results["summary"].contains("by_view") && results["config"].contains("views")) {
    const json& c = results["config"];
    const bool several = c["views"].size() > 1 || c["view_azimuths"].size() > 1 ||
                         (c.contains("sweep") && !c["sweep"]["views"].empty());
    if (several)
      for (const char* comp : {"total", "diffuse"}) v.push_back(view_table(results, comp));
  }
  for (int k : scales) v.push_back(method_table(results, "all", "total", k, true));
  for (int k : scales) v.push_back(method_table(results, "all", "total", k, false));
  v.push_back(best_table(results, true));
  v.push_back(best_table(results, false));
  if (results["config"]["normal_ablation"].get<bool>()) v.push_back(ablation_table(results));
  if (results["config"]["widened"].get<bool>()) {
    v.push_back(widened_table(results, "total"));
    v.push_back(widened_table(results, "specular"));
  }
  for (const auto& mat : results["config"]["materials"])
    for (const auto& comp : kComponents)
      for (int k : scales) v.push_back(method_table(results, mat, comp, k, true));
  return v;
}

// SVG: mean |ratio − 1| (over directional lights, total component, all materials) against log2 k, one line
// per method.
std::string plot_svg(const json& results, bool use_bias) {
  const auto scales = results["config"]["scales"].get<std::vector<int>>();
  std::map<std::string, std::vector<double>> ys;
  double ymax = 0;
  const auto methods = methods_of(results);
  for (const auto& m : methods) {
    for (int k : scales) {
      double s = 0;
      int n = 0;
      for (const auto& c : results["summary"]["cells"])
        if (c["material"] == "all" && c["component"] == "total" && c["scale"] == k &&
            c["methods"].contains(m) && main_view(results, c)) {
          s += c["methods"][m][use_bias ? "abs_dev" : "rmse_footprint_rel"].get<double>(), ++n;
        }
      const double y = n ? s / n : 0;
      ys[m].push_back(y), ymax = std::max(ymax, y);
    }
  }
  if (!(ymax > 0)) ymax = 1;
  const int W = 680, H = 300, L = 60, R = 300, T = 20, B = 40;
  auto X = [&](std::size_t i) {
    return L + (scales.size() > 1 ? double(i) / double(scales.size() - 1) : 0.5) * (W - L - R);
  };
  auto Y = [&](double y) { return T + (1 - y / ymax) * (H - T - B); };
  // One colour per method (ColorBrewer Set1, then Dark2; dashed once the colours run out).
  static const std::vector<std::string> colors = {"#000",    "#888",    "#e41a1c", "#377eb8", "#4daf4a",
                                                  "#984ea3", "#ff7f00", "#a65628", "#f781bf", "#1b9e77",
                                                  "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02"};
  std::string s =
      fmt::format("<svg width={} height={} xmlns='http://www.w3.org/2000/svg' font-size='11'>", W, H);
  s += fmt::format("<line x1={} y1={} x2={} y2={} stroke='#000'/>", L, H - B, W - R, H - B);
  s += fmt::format("<line x1={} y1={} x2={} y2={} stroke='#000'/>", L, T, L, H - B);
  for (int i = 0; i <= 4; ++i) {
    const double y = ymax * i / 4;
    s += fmt::format("<text x={} y={:.1f} text-anchor='end'>{:.3f}</text>", L - 4, Y(y) + 4, y);
  }
  for (std::size_t i = 0; i < scales.size(); ++i)
    s += fmt::format("<text x={:.1f} y={} text-anchor='middle'>k = {}</text>", X(i), H - B + 16, scales[i]);
  s += fmt::format("<text x={} y={} text-anchor='middle'>{}</text>", (L + W - R) / 2, H - 6,
                   use_bias ? "mean |term / ground truth − 1| over the lights (total)"
                            : "mean footprint RMSE / GT mean over the lights (total)");
  for (std::size_t mi = 0; mi < methods.size(); ++mi) {
    const auto& y = ys[methods[mi]];
    std::string pts;
    for (std::size_t i = 0; i < y.size(); ++i) pts += fmt::format("{:.1f},{:.1f} ", X(i), Y(y[i]));
    const std::string& col = colors[mi % colors.size()];
    s += fmt::format("<polyline fill='none' stroke='{}' stroke-width='2'{} points='{}'/>", col,
                     mi >= colors.size() ? " stroke-dasharray='5,3'" : "", pts);
    s += fmt::format("<text x={} y={} fill='{}'>{}</text>", W - R + 8, T + 14 * int(mi) + 10, col,
                     esc(methods[mi]));
  }
  return s + "</svg>\n";
}

}  // namespace

std::string summary_markdown(const json& results) {
  std::string s =
      fmt::format("### Study `{}`: verdict tables\n\n", results["config"]["name"].get<std::string>());
  int met = 0, n = 0;
  for (const auto& g : results["ground_truth"]) met += g["floors_met"].get<bool>(), ++n;
  s += fmt::format("Ground truth: {} of {} configurations met the noise-floor rule.\n\n", met, n);
  for (const auto& t : all_tables(results)) s += md(t);
  return s;
}

void write_study_html(const json& results, const std::filesystem::path& out) {
  std::string h =
      "<!doctype html><html><head><meta charset='utf-8'><title>microshadow multiscale study</title><style>"
      "body{font-family:sans-serif;margin:20px;max-width:1400px} table{border-collapse:collapse;margin:6px 0 "
      "14px}"
      "td,th{border:1px solid #ccc;padding:2px 6px;font-size:12px;text-align:right} th{background:#eee}"
      "td.best{background:#cfc;font-weight:bold} .note{font-size:12px;color:#444} "
      "img{image-rendering:pixelated;"
      "width:192px;height:192px} figure{display:inline-block;margin:4px;font-size:11px;text-align:center}"
      "</style></head><body>\n";
  const json& c = results["config"];
  h += fmt::format(
      "<h1>Multiscale micro-shadowing study ({})</h1><p>A fine {}² height field per material is the real "
      "surface. "
      "The ground truth ray-traces it (base-roughness GGX + Lambert); every term renders the texture set "
      "derived "
      "from it at 1/k resolution (filtered normal, mean visibility) with the same camera; each pixel covers "
      "k × k "
      "fine texels. Ratios are mean luminance over the whole view; footprint RMSE averages both images over "
      "{}×{} "
      "pixels first. See docs/study.md.</p>\n",
      esc(c["name"].get<std::string>()), c["fine_size"].get<int>(), c["footprint"].get<int>(),
      c["footprint"].get<int>());
  h += "<h2>Error against scale</h2>" + plot_svg(results, true) + plot_svg(results, false);
  h += "<h2>Verdict tables</h2>\n";
  for (const auto& t : all_tables(results)) h += html(t);
  h += "<h2>Images (total component; difference: red = term brighter, blue = darker, ×4)</h2>\n";
  std::string last;
  for (const auto& im : results["images"]) {
    const std::string group =
        fmt::format("{} {} k = {} {}", im["material"].get<std::string>(), im["shape"].get<std::string>(),
                    im["scale"].get<int>(), im["light"].get<std::string>());
    if (group != last) h += "<h3>" + esc(group) + "</h3>\n", last = group;
    h += "<figure><img src='" + url_path(im["image"].get<std::string>()) + "'><br>" +
         esc(im["method"].get<std::string>());
    if (im.contains("diff")) h += "<br><img src='" + url_path(im["diff"].get<std::string>()) + "'>";
    h += "</figure>\n";
  }
  h += "<h2>Ground truth</h2><table><tr><th>material</th><th>shape</th><th>k</th><th>light</th><th>spp</th>"
       "<th>floors met</th><th>bias floor (total)</th><th>footprint floor / mean (total)</th></tr>\n";
  for (const auto& g : results["ground_truth"]) {
    const json& t = g["components"]["total"];
    h += fmt::format(
        "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
        esc(g["material"].get<std::string>()), esc(g["shape"].get<std::string>()), g["scale"].get<int>(),
        esc(g["light"].get<std::string>()), g["spp"].get<int>(), g["floors_met"].get<bool>() ? "yes" : "no",
        fmt::format("{:.4f}", t["bias_floor"].is_number() ? t["bias_floor"].get<double>() : 0.0),
        fmt::format("{:.4f}", t["rmse_footprint_floor_rel"].is_number()
                                  ? t["rmse_footprint_floor_rel"].get<double>()
                                  : 0.0));
  }
  h += "</table><p>Raw data: <a href='results.json'>results.json</a>, <a href='results.csv'>results.csv</a>, "
       "<a href='summary.md'>summary.md</a>.</p></body></html>\n";
  io::write_file_atomic(out / "study.html", h);
}

}  // namespace msh::study
