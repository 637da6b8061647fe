// The study's area-light section (docs/area-lights.md): per light and scale, each term's mean-radiance
// ratio and footprint RMSE with micro-shadowing per light sample, at the representative point and integrated
// over the light (study/study.h: summarize_area, area_summary_markdown).
#include <fmt/format.h>
#include <microshadow/study/study.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace msh::study {

using json = nlohmann::json;

namespace {

double num_or_nan(const json& j) { return j.is_number() ? j.get<double>() : std::nan(""); }
std::string f3(double x) { return std::isfinite(x) ? fmt::format("{:.3f}", x) : "–"; }

const char* kModes[3] = {"sampled", "representative", "integrated"};
const char* kModeShort[3] = {"S", "R", "I"};

}  // namespace

json summarize_area(const json& rows) {
  // cells keyed by material | scale | component | light, in the rows' order.
  std::vector<std::string> order;
  std::map<std::string, json> cells;
  for (const auto& r : rows) {
    if (!r.contains("area_ms")) continue;
    const std::string key =
        fmt::format("{}|{}|{}|{}", r["material"].get<std::string>(), r["scale"].get<int>(),
                    r["component"].get<std::string>(), r["light"].get<std::string>());
    if (!cells.count(key)) {
      order.push_back(key);
      cells[key] = {{"material", r["material"]},
                    {"shape", r["shape"]},
                    {"scale", r["scale"]},
                    {"component", r["component"]},
                    {"light", r["light"]},
                    {"light_type", r["light_type"]},
                    {"elevation", r["elevation"]},
                    {"light_radius_deg", r["light_radius_deg"]},
                    {"gt_mean", r["gt_mean"]["whole"]},
                    {"methods", json::object()}};
    }
    const double gm = num_or_nan(r["gt_mean"]["whole"]);
    cells[key]["methods"][r["method"].get<std::string>() + "/" + r["area_ms"].get<std::string>()] = {
        {"bias", r["bias"]["whole"]},
        {"bias_stderr", r["bias_stderr"]["whole"]},
        {"rmse_footprint_rel", num_or_nan(r["rmse_footprint"]["whole"]) / gm},
        {"rmse_footprint_floor_rel", num_or_nan(r["rmse_footprint_floor"]["whole"]) / gm}};
  }
  json out = json::array();
  for (const auto& k : order) {
    json& c = cells[k];
    for (auto& [m, e] : c["methods"].items())
      for (const char* f : {"rmse_footprint_rel", "rmse_footprint_floor_rel"})
        if (!std::isfinite(num_or_nan(e[f]))) e[f] = nullptr;
    out.push_back(c);
  }
  return out;
}

namespace {

// (material|scale|component, component) of the area summary's cells, in their order.
using AreaGroups = std::vector<std::pair<std::string, std::string>>;

// The representative point against the integrated form (or the per-sample term) of the same term: one table
// per group.
std::string representative_tables(const json& results, const AreaGroups& group_order) {
  std::string s;
  const json& rep = results["area_representative"];
  std::vector<std::string> rep_terms;
  for (const auto& r : rep)
    if (std::find(rep_terms.begin(), rep_terms.end(), r["method"].get<std::string>()) == rep_terms.end())
      rep_terms.push_back(r["method"]);
  for (const auto& [g, comp] : group_order) {
    const auto p1 = g.find('|'), p2 = g.rfind('|');
    const std::string mat = g.substr(0, p1);
    const int k = std::stoi(g.substr(p1 + 1, p2 - p1 - 1));
    s += fmt::format(
        "#### Representative point against integrated (I) / per-sample (S) — {}, k = {}, {}: mean ratio "
        "R/I, "
        "footprint RMSE of R − I / GT mean, per-pixel RMSE / GT mean\n\n| light | radius | elev. |",
        mat, k, comp);
    std::string sep = "|---|---:|---:|";
    for (const auto& t : rep_terms) s += " " + t + " |", sep += "---:|";
    s += "\n" + sep + "\n";
    std::string last;
    for (const auto& r : rep) {
      if (r["material"] != mat || r["scale"] != k || r["component"] != comp) continue;
      if (r["light"] == last) continue;
      last = r["light"];
      s += fmt::format("| {} | {}° | {}° |", r["light_type"].get<std::string>(),
                       r["light_radius_deg"].get<double>(), r["elevation"].get<double>());
      for (const auto& t : rep_terms) {
        std::string v = "–";
        for (const auto& q : rep)
          if (q["light"] == last && q["material"] == mat && q["scale"] == k && q["component"] == comp &&
              q["method"] == t)
            v = fmt::format("{} / {} / {} ({})", f3(num_or_nan(q["ratio"])),
                            f3(num_or_nan(q["rmse_footprint_rel"])), f3(num_or_nan(q["rmse_rel"])),
                            q["against"] == "integrated" ? "I" : "S");
        s += " " + v + " |";
      }
      s += "\n";
    }
    s += "\n";
  }

  return s;
}

// Per group, each term's mean radiance ratio per mode, then its footprint RMSE.
std::string term_tables(const json& cells, const AreaGroups& group_order,
                        const std::vector<std::string>& term_order) {
  std::string s;
  for (const bool rmse : {false, true})
    for (const auto& [g, comp] : group_order) {
      const auto p1 = g.find('|'), p2 = g.rfind('|');
      s += fmt::format("#### {} — {}, k = {}, {}\n\n",
                       rmse ? "Footprint RMSE / GT mean" : "Mean radiance ratio", g.substr(0, p1),
                       g.substr(p1 + 1, p2 - p1 - 1), comp);
      s += "| light | radius | elev. | GT mean |";
      std::string sep = "|---|---:|---:|---:|";
      for (const auto& t : term_order) {
        int n = 0;
        for (const char* m : kModes)
          for (const auto& c : cells)
            if (c["methods"].contains(t + "/" + m)) {
              ++n;
              break;
            }
        std::string modes;
        for (int i = 0; i < 3; ++i)
          for (const auto& c : cells)
            if (c["methods"].contains(t + "/" + kModes[i])) {
              modes += std::string(modes.empty() ? "" : " / ") + kModeShort[i];
              break;
            }
        s += fmt::format(" {}{} |", t, n > 1 ? " (" + modes + ")" : "");
        sep += "---:|";
      }
      if (!rmse) s += " ± |", sep += "---:|";
      s += "\n" + sep + "\n";
      for (const auto& c : cells) {
        if (fmt::format("{}|{}|{}", c["material"].get<std::string>(), c["scale"].get<int>(),
                        c["component"].get<std::string>()) != g)
          continue;
        double se = 0;
        for (const auto& [m, e] : c["methods"].items()) se = std::max(se, num_or_nan(e["bias_stderr"]));
        s += fmt::format("| {} | {}° | {}° | {} |", c["light_type"].get<std::string>(),
                         c["light_radius_deg"].get<double>(), c["elevation"].get<double>(),
                         f3(num_or_nan(c["gt_mean"])));
        for (const auto& t : term_order) {
          std::string v;
          for (const char* m : kModes) {
            if (!c["methods"].contains(t + "/" + m)) continue;
            const json& e = c["methods"][t + "/" + m];
            const std::string x = rmse ? fmt::format("{} [{}]", f3(num_or_nan(e["rmse_footprint_rel"])),
                                                     f3(num_or_nan(e["rmse_footprint_floor_rel"])))
                                       : f3(num_or_nan(e["bias"]));
            v += (v.empty() ? "" : " / ") + x;
          }
          s += " " + v + " |";
        }
        s += rmse ? "\n" : fmt::format(" {:.3f} |\n", se);
      }
      s += "\n";
    }
  return s;
}

}  // namespace

std::string area_summary_markdown(const json& results) {
  const json& cells = results["area_summary"];
  std::set<std::string> terms;
  std::vector<std::string> term_order;
  for (const auto& c : cells)
    for (const auto& [m, e] : c["methods"].items()) {
      const std::string t = m.substr(0, m.find('/'));
      if (terms.insert(t).second) term_order.push_back(t);
    }
  std::string s =
      "### Area lights: micro-shadowing per light sample (S), at the representative point (R), integrated "
      "over the light (I)\n\n"
      "Mean radiance term / ground truth over the whole view (1 = exact; ± = the ground truth's standard "
      "error on the ratio), then the footprint RMSE / GT mean (its floor in brackets).\n\n";
  std::set<std::string> groups;
  AreaGroups group_order;
  for (const auto& c : cells) {
    const std::string g = fmt::format("{}|{}|{}", c["material"].get<std::string>(), c["scale"].get<int>(),
                                      c["component"].get<std::string>());
    if (groups.insert(g).second) group_order.push_back({g, c["component"]});
  }
  if (results.contains("area_representative")) s += representative_tables(results, group_order);
  s += term_tables(cells, group_order, term_order);
  return s;
}

}  // namespace msh::study
