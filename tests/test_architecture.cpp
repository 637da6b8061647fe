// The dependency rules of docs/architecture.md, checked on the headers as they are: the header-only core
// (every header of math, microfacet, occlusion, bsdf, lut, reference and filter outside a runtime/ folder)
// includes only the C++ standard library's computational headers and other core headers, and each area
// includes only the areas the document allows. A header that breaks a rule fails with its name and line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kInclude = fs::path(MSH_SOURCE_DIR) / "include" / "microshadow";

struct Include {
  fs::path file;
  int line;
  std::string target;  // what is between < > or " "
};

std::vector<Include> includes_of(const fs::path& f) {
  std::vector<Include> out;
  std::ifstream in(f);
  const std::regex re(R"(^\s*#\s*include\s*[<"]([^>"]+)[>"])");
  std::string s;
  for (int n = 1; std::getline(in, s); ++n) {
    std::smatch m;
    if (std::regex_search(s, m, re)) out.push_back({f, n, m[1]});
  }
  return out;
}

// "occlusion" for include/microshadow/occlusion/x.h; "occlusion/runtime" for its runtime folder.
std::string area_of(const fs::path& header) {
  const fs::path rel = fs::relative(header, kInclude);
  auto it = rel.begin();
  std::string area = it->string();
  if (++it != rel.end() && std::next(it) != rel.end() && it->string() == "runtime") area += "/runtime";
  return area;
}

const std::set<std::string> kCoreAreas = {"math", "microfacet", "occlusion", "bsdf",
                                          "lut",  "reference",  "filter"};

// The standard headers a core header may use: computation, no I/O, no threads, no type erasure (<memory>:
// GTR shares its precomputed Λ table between copies).
const std::set<std::string> kCoreStd = {"algorithm", "array",    "cmath",   "complex",     "concepts",
                                        "cstddef",   "cstdint",  "cstring", "limits",      "memory",
                                        "numeric",   "optional", "string",  "string_view", "type_traits",
                                        "utility",   "vector",   "bit",     "span"};

// Which areas each area may include (docs/architecture.md, "Dependency rules"). runtime/ folders may also
// include io and the third-party libraries.
const std::map<std::string, std::set<std::string>> kAllowed = {
    {"math", {}},
    {"io", {}},
    {"microfacet", {"math"}},
    {"filter", {"math"}},
    {"occlusion", {"math", "microfacet"}},
    {"bsdf", {"math", "microfacet"}},
    {"lut", {"math", "microfacet", "occlusion"}},
    {"reference", {"math", "microfacet", "occlusion", "bsdf"}},
    {"render", {"math", "microfacet", "occlusion", "bsdf", "lut", "reference", "filter", "io"}},
    {"study", {"math", "microfacet", "occlusion", "bsdf", "lut", "reference", "filter", "io", "render"}},
};

bool is_core(const std::string& area) { return kCoreAreas.count(area) > 0; }

std::string base_area(const std::string& area) { return area.substr(0, area.find('/')); }

TEST(Architecture, HeadersFollowTheDependencyRules) {
  ASSERT_TRUE(fs::is_directory(kInclude)) << kInclude;
  int headers = 0;
  for (const auto& e : fs::recursive_directory_iterator(kInclude)) {
    if (!e.is_regular_file() || e.path().extension() != ".h") continue;
    if (e.path().parent_path() == kInclude) continue;  // the umbrella header of the core, if any
    ++headers;
    const std::string area = area_of(e.path());
    const std::string base = base_area(area);
    const bool runtime = area.find("/runtime") != std::string::npos;
    ASSERT_TRUE(kAllowed.count(base)) << e.path() << ": area '" << base << "' is not in docs/architecture.md";
    for (const Include& inc : includes_of(e.path())) {
      const std::string where =
          inc.file.string() + ":" + std::to_string(inc.line) + " includes " + inc.target;
      if (inc.target.rfind("microshadow/", 0) == 0) {
        const std::string to = area_of(kInclude / inc.target.substr(12));
        const std::string to_base = base_area(to);
        if (to_base == base) {
          // Within an area: the core never includes its own runtime folder.
          EXPECT_FALSE(!runtime && is_core(base) && to != area && to.find("/runtime") != std::string::npos)
              << where;
          continue;
        }
        const bool allowed = kAllowed.at(base).count(to_base) > 0 || (runtime && to_base == "io");
        EXPECT_TRUE(allowed) << where << " (" << base << " may not depend on " << to_base << ")";
        if (is_core(base) && !runtime) {
          EXPECT_TRUE(is_core(to_base) && to.find("/runtime") == std::string::npos)
              << where << " (the core may include only core headers)";
        }
      } else if (is_core(base) && !runtime) {
        EXPECT_TRUE(kCoreStd.count(inc.target) > 0)
            << where << " (a core header uses only computational standard headers)";
      }
    }
  }
  EXPECT_GT(headers, 40);
}

// The classification the rules rest on.
TEST(Architecture, AreaOfAHeader) {
  EXPECT_EQ(area_of(kInclude / "lut" / "runtime" / "x.h"), "lut/runtime");
  EXPECT_EQ(area_of(kInclude / "lut" / "x.h"), "lut");
  EXPECT_EQ(area_of(kInclude / "bsdf" / "runtime" / "x.h"), "bsdf/runtime");
  EXPECT_TRUE(is_core("occlusion"));
  EXPECT_FALSE(is_core("render"));
}

}  // namespace
